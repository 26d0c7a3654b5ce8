#!/usr/bin/env python3
"""Chapter 01's diagram: a grid of 16x16-thread blocks laid over a 40x24-pixel image, the
threads that hang over its edges, one thread's coordinates and one warp
(book/images/01_grid_of_blocks.svg).

  tools/diagrams/ch01.py [OUT_DIR]     (default: book/images)
"""
import sys
from pathlib import Path

import matplotlib

matplotlib.use("svg")
matplotlib.rcParams["svg.hashsalt"] = "rt-course"  # the same file on every run
matplotlib.rcParams["svg.fonttype"] = "none"  # text stays text
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import Rectangle  # noqa: E402

BLUE, GREY, RED, ORANGE = "#2a7ab0", "#555555", "#c0392b", "#e08a1e"
WIDTH, HEIGHT, BLOCK = 40, 24, 16  # the image and the block, in pixels and threads
GRID_X, GRID_Y = -(-WIDTH // BLOCK), -(-HEIGHT // BLOCK)  # blocks_to_cover


def main():
    out = Path(sys.argv[1] if len(sys.argv) > 1 else "book/images")
    fig, ax = plt.subplots(figsize=(9.0, 5.4))
    ax.set_xlim(-2, GRID_X * BLOCK + 24)
    ax.set_ylim(GRID_Y * BLOCK + 3, -5)  # row 0 at the top, as in the course's images
    ax.set_aspect("equal")
    ax.axis("off")

    # Every thread of the grid: inside the image a pixel, outside it the overhang.
    right, bottom = GRID_X * BLOCK, GRID_Y * BLOCK
    ax.add_patch(Rectangle((0, 0), right, bottom, facecolor="#e4e4e4", edgecolor="#bbbbbb",
                           hatch="////"))
    ax.add_patch(Rectangle((0, 0), WIDTH, HEIGHT, facecolor="#eef4fa", edgecolor="none"))
    for x in range(right + 1):
        ax.plot([x, x], [0, bottom], color="#c8d6e4", linewidth=0.3)
    for y in range(bottom + 1):
        ax.plot([0, right], [y, y], color="#c8d6e4", linewidth=0.3)
    # One warp: threads 0..31 of block (1, 0) are its first two rows.
    ax.add_patch(Rectangle((BLOCK, 0), BLOCK, 2, facecolor=ORANGE, alpha=0.45, linewidth=0))
    # The blocks.
    for by in range(GRID_Y):
        for bx in range(GRID_X):
            ax.add_patch(Rectangle((bx * BLOCK, by * BLOCK), BLOCK, BLOCK, fill=False,
                                   edgecolor=BLUE, linewidth=1.6))
            ax.text(bx * BLOCK + BLOCK / 2, by * BLOCK + BLOCK / 2,
                    f"blockIdx\n({bx}, {by})", ha="center", va="center", fontsize=9,
                    color=BLUE, alpha=0.75)
    # The image's edge.
    ax.add_patch(Rectangle((0, 0), WIDTH, HEIGHT, fill=False, edgecolor=RED, linewidth=2.2))
    ax.text(WIDTH / 2, -1.2, f"image: {WIDTH} x {HEIGHT} pixels", ha="center", va="bottom",
            fontsize=10, color=RED)
    ax.text(GRID_X * BLOCK / 2, GRID_Y * BLOCK + 1.0,
            f"grid: {GRID_X} x {GRID_Y} blocks of {BLOCK} x {BLOCK} threads = "
            f"{GRID_X * BLOCK} x {GRID_Y * BLOCK} threads", ha="center", va="top",
            fontsize=10, color=BLUE)

    # One thread and its coordinates.
    tx, ty = 5, 3
    px, py = BLOCK + tx, BLOCK + ty
    ax.add_patch(Rectangle((px, py), 1, 1, facecolor=RED, edgecolor=RED))
    ax.annotate(f"threadIdx = ({tx}, {ty}) in blockIdx = (1, 1)\n"
                f"x = 1 * 16 + {tx} = {px}\ny = 1 * 16 + {ty} = {py}",
                xy=(px + 1, py + 0.5), xytext=(GRID_X * BLOCK + 1.5, 21), fontsize=9,
                color=GREY, va="center", arrowprops=dict(arrowstyle="-|>", color=RED, lw=1))
    ax.annotate("one warp: 32 threads,\nthe block's first two rows", xy=(2 * BLOCK, 1),
                xytext=(GRID_X * BLOCK + 1.5, 4), fontsize=9, color=GREY, va="center",
                arrowprops=dict(arrowstyle="-|>", color=ORANGE, lw=1))
    ax.annotate("overhang: threads with no pixel\n(x >= width or y >= height)",
                xy=(44, 28), xytext=(GRID_X * BLOCK + 1.5, 30), fontsize=9, color=GREY,
                va="center", arrowprops=dict(arrowstyle="-|>", color=GREY, lw=1))

    out.mkdir(parents=True, exist_ok=True)
    fig.savefig(out / "01_grid_of_blocks.svg", bbox_inches="tight", metadata={"Date": None})


if __name__ == "__main__":
    main()
