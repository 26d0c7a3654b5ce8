#!/usr/bin/env python3
"""Chapter 10's diagrams and plots (book/images/10_*): Karras's tree over eight sorted
Morton codes, each interior node made by its own thread, and the moving scene's frames, rebuilt
against refitted, from the CSVs the program wrote into book/data: the 2-core machine's (SVG) and
the H200's, torus and dragon, each frame's tree, collapse and trace stacked (PNG).

  tools/diagrams/ch10.py [OUT_DIR]     (default: book/images)
"""
import csv
import sys
from pathlib import Path

import matplotlib

matplotlib.use("svg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import FancyBboxPatch  # noqa: E402

BLUE, GREY, RED, GREEN = "#2a7ab0", "#555555", "#c0392b", "#2e8b57"
ROOT = Path(__file__).resolve().parents[2]
ANIMATION = ROOT / "book" / "data" / "10_animation_cpu.csv"
GPU_ANIMATIONS = (  # CSV, the scene's name, the PNG
    ("10_animation_h200.csv", "torus, 105 168 triangles", "10_animation_h200.png"),
    ("10_animation_dragon_h200.csv", "dragon, 876 726 triangles",
     "10_animation_dragon_h200.png"),
)
CODES = [1, 2, 4, 5, 19, 24, 25, 30]  # the example of tests/10_gpu_build (5-bit codes)
BITS = 5


def save(fig, path):
    fig.savefig(path, format="svg", metadata={"Date": None}, bbox_inches="tight")


def delta(i, j):
    """Common prefix of the 5-bit codes of leaves i and j; -1 outside the array."""
    if j < 0 or j >= len(CODES):
        return -1
    x = CODES[i] ^ CODES[j]
    return BITS - x.bit_length() if x else BITS + 32 - (i ^ j).bit_length()


def karras_node(i):
    """Interior node i: (first, last, split), as chapters/10_gpu_build/karras.h finds it."""
    d = 1 if delta(i, i + 1) - delta(i, i - 1) >= 0 else -1
    delta_min = delta(i, i - d)
    step = 2
    while delta(i, i + step * d) > delta_min:
        step *= 2
    length, t = 0, step // 2
    while t >= 1:
        if delta(i, i + (length + t) * d) > delta_min:
            length += t
        t //= 2
    j = i + length * d
    delta_node, s, divisor = delta(i, j), 0, 2
    while True:
        t = (length + divisor - 1) // divisor
        if delta(i, i + (s + t) * d) > delta_node:
            s += t
        if t <= 1:
            break
        divisor *= 2
    split = i + s * d + min(d, 0)
    return min(i, j), max(i, j), split


def karras_tree(out):
    n = len(CODES)
    nodes = {i: karras_node(i) for i in range(n - 1)}
    depth = {0: 0}
    order = [0]  # a walk from the root gives every interior node its depth
    while order:
        i = order.pop()
        first, last, split = nodes[i]
        for child, leaf in ((split, first == split), (split + 1, last == split + 1)):
            if not leaf:
                depth[child] = depth[i] + 1
                order.append(child)
    deepest = max(depth.values())
    fig, ax = plt.subplots(figsize=(10, 5.2))
    ax.set_xlim(-0.8, n - 0.2)
    ax.set_ylim(-1.5, deepest + 1.4)
    ax.axis("off")

    def x_of(i):
        first, last, split = nodes[i]
        return split + 0.5

    def y_of(level):
        return deepest + 1 - level

    for k, code in enumerate(CODES):
        ax.add_patch(FancyBboxPatch((k - 0.38, -0.35), 0.76, 0.7, boxstyle="round,pad=0.02",
                                    facecolor="#eef5fb", edgecolor=BLUE))
        ax.text(k, 0.08, f"{code:05b}", ha="center", va="center", fontsize=10,
                family="monospace")
        ax.text(k, -0.6, f"leaf {k}", ha="center", va="top", fontsize=8, color=GREY)
    for i, (first, last, split) in nodes.items():
        x, y = x_of(i), y_of(depth[i])
        for child, leaf in ((split, first == split), (split + 1, last == split + 1)):
            cx, cy = (child, 0.35) if leaf else (x_of(child), y_of(depth[child]) + 0.25)
            ax.plot([x, cx], [y - 0.25, cy], color=GREY, linewidth=1)
        ax.add_patch(FancyBboxPatch((x - 0.42, y - 0.25), 0.84, 0.5, boxstyle="round,pad=0.02",
                                    facecolor="#fdf2e9", edgecolor=RED))
        ax.text(x, y, f"node {i}\n{first}..{last}", ha="center", va="center", fontsize=8)
        ax.plot([i, x], [0.35, y - 0.25], color=RED, linestyle=":", linewidth=1.0)
    ax.text(-0.7, -1.05, "Thread i makes interior node i. Leaf i is one end of its range "
            "(dotted); the codes alone give the other end and the split (solid: the children).",
            fontsize=9, color=GREY, va="top")
    save(fig, out / "10_karras_tree.svg")
    plt.close(fig)


def animation_plot(out):
    with ANIMATION.open() as f:
        rows = list(csv.DictReader(f))
    frames = [int(r["frame"]) for r in rows]
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4))
    for update, colour in (("rebuild", BLUE), ("refit", RED)):
        left.plot(frames, [float(r[f"{update}_tree_ms"]) for r in rows], color=colour,
                  label=f"{update}: tree")
        left.plot(frames, [float(r[f"{update}_trace_ms"]) for r in rows], color=colour,
                  linestyle="--", label=f"{update}: shaded frame")
        first = float(rows[0][f"{update}_sah_cost"])
        right.plot(frames, [float(r[f"{update}_sah_cost"]) / first for r in rows],
                   color=colour, label=update)
    left.set_xlabel("frame")
    left.set_ylabel("ms (2-core development machine)")
    left.set_title("Time per frame: tree and shaded frame")
    left.legend(fontsize=8)
    right.set_xlabel("frame")
    right.set_ylabel("SAH cost / frame 0's")
    right.set_title("The tree's SAH cost as the torus ripples")
    right.legend(fontsize=8)
    save(fig, out / "10_refit_vs_rebuild.svg")
    plt.close(fig)


def gpu_animation_plot(out, csv_name, scene, png_name):
    """Rebuild beside refit, each frame's tree, collapse and trace stacked. Frame 0 is left
    out: both start with a build, and the rebuild's first frame also pays the first launches."""
    with (ROOT / "book" / "data" / csv_name).open() as f:
        rows = list(csv.DictReader(f))[1:]
    frames = [int(r["frame"]) for r in rows]
    fig, axes = plt.subplots(1, 2, figsize=(11, 4), sharey=True)
    for ax, update in zip(axes, ("rebuild", "refit")):
        parts = [[float(r[f"{update}_{part}_ms"]) for r in rows]
                 for part in ("tree", "collapse", "trace")]
        ax.stackplot(frames, *parts, colors=(BLUE, GREEN, RED), alpha=0.85,
                     labels=("tree (build or refit)", "collapse to 4-wide", "shaded frame"))
        ax.set_xlabel("frame")
        ax.set_title(update)
    axes[0].set_ylabel("ms per frame, CUDA events (H200, 1920x1080)")
    axes[1].legend(fontsize=8, loc="upper left")
    fig.suptitle(f"The moving {scene}: rebuilt against refitted, frames 1-{frames[-1]}")
    fig.savefig(out / png_name, format="png", dpi=100, metadata={"Software": None},
                bbox_inches="tight")
    plt.close(fig)


def main():
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "book" / "images"
    out.mkdir(parents=True, exist_ok=True)
    karras_tree(out)
    animation_plot(out)
    for csv_name, scene, png_name in GPU_ANIMATIONS:
        gpu_animation_plot(out, csv_name, scene, png_name)


if __name__ == "__main__":
    main()
