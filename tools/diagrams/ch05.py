#!/usr/bin/env python3
"""Chapter 05's diagram: from an OBJ file to the indexed mesh, the loader's four steps and what
a small file becomes (book/images/05_obj_to_mesh.svg).

  tools/diagrams/ch05.py [OUT_DIR]     (default: book/images)
"""
import sys
from pathlib import Path

import matplotlib

matplotlib.use("svg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import FancyArrowPatch, FancyBboxPatch  # noqa: E402

BLUE, GREY, RED = "#2a7ab0", "#555555", "#c0392b"


def box(ax, x, y, w, h, title, body, colour=BLUE):
    ax.add_patch(FancyBboxPatch((x, y), w, h, boxstyle="round,pad=0.02,rounding_size=0.08",
                                facecolor="white", edgecolor=colour, linewidth=1.2))
    ax.text(x + w / 2, y + h - 0.17, title, ha="center", va="top", fontsize=9.5,
            fontweight="bold", color=colour)
    ax.text(x + w / 2, y + h - 0.5, body, ha="center", va="top", fontsize=7.8, color=GREY,
            linespacing=1.35)


def arrow(ax, start, end, colour=GREY, text=None):
    ax.add_patch(FancyArrowPatch(start, end, arrowstyle="-|>", mutation_scale=12,
                                 color=colour, linewidth=1.1))
    if text:
        ax.text((start[0] + end[0]) / 2, (start[1] + end[1]) / 2 + 0.1, text, ha="center",
                va="bottom", fontsize=7.5, color=colour)


def main():
    out = Path(sys.argv[1] if len(sys.argv) > 1 else "book/images")
    plt.rcParams.update({"svg.hashsalt": "rt-course-ch05", "font.family": "DejaVu Sans"})
    fig, ax = plt.subplots(figsize=(11, 5.6))
    ax.set_xlim(0, 16.5)
    ax.set_ylim(0, 8)
    ax.axis("off")

    # The four steps of obj_loader.cpp, left to right.
    steps = [
        ("file", ".obj or .obj.gz\nany name, any bytes", GREY),
        ("1. bytes", "regular file only\nsize cap; gzip by its\nfirst two bytes, unpacked\n"
         "in chunks under the cap", BLUE),
        ("2. line checks", "every statement the mesh\nneeds, with its line number:\nnumbers, "
         "corners, indices\nin range; counts capped;\nunused statements blanked", BLUE),
        ("3. tinyobjloader", "parses text now known\nto be well formed;\n0-based indices", BLUE),
        ("4. conversion", "polygons to fans;\nevery index checked\nagain against its array", BLUE),
    ]
    x = 0.2
    for i, (title, body, colour) in enumerate(steps):
        box(ax, x, 5.2, 2.9, 2.5, title, body, colour)
        if i:
            arrow(ax, (x - 0.45, 6.45), (x - 0.02, 6.45))
        x += 3.3
    ax.text(3.5, 4.8, "at any step, any problem ends the load with one line, "
            "file:line: what is wrong (InputError), and nothing half built",
            fontsize=8.5, color=RED, va="center")

    # A small file and the mesh it becomes.
    obj = ("v 0 0 0        # 1\nv 1 0 0        # 2\nv 1 1 0        # 3\nv 0 1 0        # 4\n"
           "v 0.5 0.5 1    # 5\nf 1 2 3 4      # a quad\nf -4 -3 5      # 2 3 5, counted back")
    ax.text(0.3, 3.9, "OBJ text", fontsize=9.5, fontweight="bold", color=GREY)
    ax.text(0.3, 3.55, obj, fontsize=8.2, family="monospace", va="top", linespacing=1.45)
    arrow(ax, (4.6, 2.2), (5.7, 2.2), GREY, "load_obj")

    ax.text(6.0, 3.9, "ObjMesh.geometry (chapter 04's Mesh)", fontsize=9.5, fontweight="bold",
            color=BLUE)
    cells = ["(0,0,0)", "(1,0,0)", "(1,1,0)", "(0,1,0)", "(.5,.5,1)"]
    for i, c in enumerate(cells):
        ax.add_patch(plt.Rectangle((6.0 + 1.3 * i, 2.85), 1.3, 0.6, facecolor="#eef5fb",
                                   edgecolor=BLUE))
        ax.text(6.65 + 1.3 * i, 3.15, c, ha="center", va="center", fontsize=8,
                family="monospace")
        ax.text(6.65 + 1.3 * i, 3.5, str(i), ha="center", va="bottom", fontsize=7, color=GREY)
    ax.text(12.6, 3.15, "vertices: 12 bytes each,\nstored once", fontsize=8, va="center",
            color=GREY)
    triangles = [("(0,1,2)", "quad, fan 1"), ("(0,2,3)", "quad, fan 2"), ("(1,2,4)", "-4 -3 5")]
    for i, (t, why) in enumerate(triangles):
        ax.add_patch(plt.Rectangle((6.0 + 1.3 * i, 1.45), 1.3, 0.6, facecolor="#fbeeee",
                                   edgecolor=RED))
        ax.text(6.65 + 1.3 * i, 1.75, t, ha="center", va="center", fontsize=8,
                family="monospace")
        ax.text(6.65 + 1.3 * i, 1.3, why, ha="center", va="top", fontsize=6.5, color=GREY,
                rotation=0)
    ax.text(10.1, 1.75, "triangles: three 0-based indices each (12 bytes);\nneighbours "
            "name the same vertex numbers", fontsize=8, va="center", color=GREY)
    ax.text(6.0, 0.45, "also: material id per triangle (-1: none); normal and texture-"
            "coordinate index triples where the file has them; bounds; counts",
            fontsize=8, color=GREY)

    fig.savefig(out / "05_obj_to_mesh.svg", format="svg", metadata={"Date": None},
                bbox_inches="tight")


if __name__ == "__main__":
    main()
