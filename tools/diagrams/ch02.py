#!/usr/bin/env python3
"""Chapter 02's diagrams: the three ways a frame reaches the window, across the PCIe bus
(book/images/02_display_paths.svg), and the life of the pixel buffer shared by CUDA and OpenGL
(book/images/02_pbo_life_cycle.svg).

  tools/diagrams/ch02.py [OUT_DIR]     (default: book/images)
"""
import sys
from pathlib import Path

import matplotlib

matplotlib.use("svg")
matplotlib.rcParams["svg.hashsalt"] = "rt-course"  # the same file on every run
matplotlib.rcParams["svg.fonttype"] = "none"  # text stays text
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import FancyArrowPatch, FancyBboxPatch, Rectangle  # noqa: E402

BLUE, GREEN, GREY, RED, ORANGE = "#2a7ab0", "#2e8b57", "#555555", "#c0392b", "#e08a1e"


def box(ax, x, y, w, h, text, colour=BLUE, size=8.5):
    ax.add_patch(FancyBboxPatch((x, y), w, h, boxstyle="round,pad=0.02,rounding_size=0.06",
                                facecolor="white", edgecolor=colour, linewidth=1.2))
    ax.text(x + w / 2, y + h / 2, text, ha="center", va="center", fontsize=size, color=colour)


def arrow(ax, start, end, colour=GREY, width=1.2, text=None, offset=(0, 0.12), style="-|>"):
    ax.add_patch(FancyArrowPatch(start, end, arrowstyle=style, mutation_scale=11,
                                 color=colour, linewidth=width, shrinkA=2, shrinkB=2))
    if text:
        ax.text((start[0] + end[0]) / 2 + offset[0], (start[1] + end[1]) / 2 + offset[1], text,
                ha="center", va="bottom", fontsize=7.5, color=colour)


def display_paths(out):
    fig, ax = plt.subplots(figsize=(10, 5.2))
    ax.set_xlim(0, 10)
    ax.set_ylim(0, 5.6)
    ax.axis("off")
    # The two sides of the bus.
    ax.add_patch(Rectangle((0.05, 0.1), 3.2, 5.0, facecolor="#f6f6f6", edgecolor="none"))
    ax.add_patch(Rectangle((4.35, 0.1), 5.6, 5.0, facecolor="#eef4fa", edgecolor="none"))
    ax.add_patch(Rectangle((3.35, 0.1), 0.9, 5.0, facecolor="#fbe9d7", edgecolor="none"))
    ax.text(1.65, 5.25, "CPU and host memory", ha="center", fontsize=10, color=GREY)
    ax.text(7.15, 5.25, "GPU and device memory", ha="center", fontsize=10, color=BLUE)
    ax.text(3.8, 5.25, "PCIe bus", ha="center", fontsize=10, color=ORANGE)

    # 1. Interop: everything stays on the GPU.
    y = 4.0
    ax.text(0.2, y + 0.25, "1. interop", fontsize=9.5, fontweight="bold", color=GREEN)
    box(ax, 4.5, y, 1.5, 0.55, "kernel writes\nthe PBO", GREEN)
    box(ax, 6.4, y, 1.4, 0.55, "PBO ->\ntexture", GREEN)
    box(ax, 8.2, y, 1.5, 0.55, "draw,\npresent", GREEN)
    arrow(ax, (6.0, y + 0.27), (6.4, y + 0.27), GREEN)
    arrow(ax, (7.8, y + 0.27), (8.2, y + 0.27), GREEN)
    ax.text(7.1, y - 0.3, "no bus crossing: copies at device-memory speed",
            ha="center", fontsize=7.5, color=GREEN)

    # 2. GPU render, copied to the host and uploaded back.
    y = 2.4
    ax.text(0.2, y + 0.55, "2. GPU + copy + upload", fontsize=9.5, fontweight="bold",
            color=ORANGE)
    box(ax, 4.5, y + 0.35, 1.5, 0.55, "kernel writes\ndevice buffer", ORANGE)
    box(ax, 1.0, y - 0.1, 1.6, 0.55, "host frame\n(pageable)", ORANGE)
    box(ax, 6.4, y - 0.55, 1.4, 0.55, "host ->\ntexture", ORANGE)
    box(ax, 8.2, y - 0.55, 1.5, 0.55, "draw,\npresent", ORANGE)
    arrow(ax, (4.5, y + 0.62), (2.6, y + 0.3), RED, 1.6, "download", (0, 0.2))
    arrow(ax, (2.6, y + 0.05), (6.4, y - 0.28), RED, 1.6, "upload", (0.2, -0.45))
    arrow(ax, (7.8, y - 0.28), (8.2, y - 0.28), ORANGE)
    ax.text(1.8, y - 0.45, "the frame crosses the bus twice", ha="center", fontsize=7.5,
            color=RED)

    # 3. CPU render, uploaded.
    y = 0.55
    ax.text(0.2, y + 0.7, "3. CPU + upload", fontsize=9.5, fontweight="bold", color=GREY)
    box(ax, 1.0, y, 1.6, 0.55, "CPU threads\nwrite the frame", GREY)
    box(ax, 6.4, y, 1.4, 0.55, "host ->\ntexture", GREY)
    box(ax, 8.2, y, 1.5, 0.55, "draw,\npresent", GREY)
    arrow(ax, (2.6, y + 0.27), (6.4, y + 0.27), RED, 1.6, "upload")
    arrow(ax, (7.8, y + 0.27), (8.2, y + 0.27), GREY)
    fig.savefig(out / "02_display_paths.svg", bbox_inches="tight", metadata={"Date": None})


def life_cycle(out):
    fig, ax = plt.subplots(figsize=(10, 4.4))
    ax.set_xlim(0, 10)
    ax.set_ylim(0, 4.6)
    ax.axis("off")
    # Once, at the start and at the end.
    box(ax, 0.0, 3.5, 2.7, 0.7, "glGenBuffers, glBufferData\n(GL owns the PBO)", GREY, 8)
    box(ax, 0.0, 2.3, 2.7, 0.7, "cudaGraphicsGLRegisterBuffer\n(once: expensive)", GREY, 8)
    box(ax, 0.0, 0.3, 2.7, 0.7, "cudaGraphicsUnregisterResource,\nthen glDeleteBuffers",
        GREY, 8)
    arrow(ax, (1.35, 3.5), (1.35, 3.0))
    arrow(ax, (1.35, 2.3), (1.35, 1.0))
    ax.text(1.45, 1.65, "at the end:\nunregister, then delete", ha="left", va="center",
            fontsize=7.5, color=GREY)

    # Every frame: a loop of five steps, coloured by who owns the buffer.
    steps = [
        (3.2, 2.9, "map: cudaGraphics-\nMapResources", GREEN),
        (5.6, 2.9, "launch: the kernel\nwrites the pixels", GREEN),
        (8.0, 2.9, "unmap\n(orders the writes\nbefore GL's reads)", GREEN),
        (8.0, 0.8, "glTexSubImage2D\nfrom the bound PBO", BLUE),
        (5.6, 0.8, "draw, present", BLUE),
    ]
    for x, y, text, colour in steps:
        box(ax, x, y, 1.8, 0.9, text, colour, 8)
    arrow(ax, (2.7, 2.65), (3.2, 3.2), GREY, text="every frame", offset=(-0.45, 0.2))
    arrow(ax, (5.0, 3.35), (5.6, 3.35), GREEN)
    arrow(ax, (7.4, 3.35), (8.0, 3.35), GREEN)
    arrow(ax, (8.9, 2.9), (8.9, 1.7), BLUE)
    arrow(ax, (8.0, 1.25), (7.4, 1.25), BLUE)
    arrow(ax, (5.6, 1.25), (4.1, 2.9), BLUE, text="next frame", offset=(-0.5, -0.2))
    ax.text(5.6, 4.2, "CUDA owns the buffer: GL must not touch it", ha="center",
            fontsize=9, color=GREEN)
    ax.text(6.5, 0.3, "GL owns the buffer: CUDA must not touch it", ha="center", fontsize=9,
            color=BLUE)
    fig.savefig(out / "02_pbo_life_cycle.svg", bbox_inches="tight", metadata={"Date": None})


def main():
    out = Path(sys.argv[1] if len(sys.argv) > 1 else "book/images")
    out.mkdir(parents=True, exist_ok=True)
    display_paths(out)
    life_cycle(out)


if __name__ == "__main__":
    main()
