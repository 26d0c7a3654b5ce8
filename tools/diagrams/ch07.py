#!/usr/bin/env python3
"""Chapter 07's diagrams (book/images/07_*.svg): a small tree laid out depth-first in one node
array, the slab test on one axis with its three traps (zero direction, NaN, -0.0), and an
object split against a spatial split of two long thin triangles.

  tools/diagrams/ch07.py [OUT_DIR]     (default: book/images)
"""
import sys
from pathlib import Path

import matplotlib

matplotlib.use("svg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import FancyArrowPatch, Rectangle  # noqa: E402

BLUE, GREY, RED, GREEN, GOLD = "#2a7ab0", "#555555", "#c0392b", "#2e8b57", "#d4a017"


def arrow(ax, start, end, colour, rad=0.0, width=1.1):
    ax.add_patch(FancyArrowPatch(start, end, arrowstyle="-|>", mutation_scale=11, color=colour,
                                 linewidth=width, connectionstyle=f"arc3,rad={rad}"))


def save(fig, path):
    fig.savefig(path, format="svg", metadata={"Date": None}, bbox_inches="tight")


def node_array(out):
    fig, ax = plt.subplots(figsize=(11, 5.2))
    ax.set_xlim(0, 22)
    ax.set_ylim(-1.0, 10.5)
    ax.axis("off")
    # The tree: interior nodes are circles numbered by their place in the array; leaves are
    # runs of triangles, held by their parent, not nodes of their own.
    nodes = {0: (8, 9.5), 1: (4.5, 7.5), 2: (2.5, 5.5), 3: (12, 7.5)}
    leaves = {"A": (1.3, 3.6, "tri 0-3"), "B": (3.7, 3.6, "tri 4-6"), "C": (6.5, 5.5, "tri 7-8"),
              "D": (10.5, 5.5, "tri 9-12"), "E": (13.5, 5.5, "tri 13-14")}
    edges = [(0, 1), (0, 3), (1, 2), (1, "C"), (2, "A"), (2, "B"), (3, "D"), (3, "E")]
    for a, b in edges:
        pa = nodes[a]
        pb = nodes[b] if isinstance(b, int) else leaves[b][:2]
        ax.plot([pa[0], pb[0]], [pa[1], pb[1]], color=GREY, linewidth=1, zorder=1)
    for i, (x, y) in nodes.items():
        ax.add_patch(plt.Circle((x, y), 0.45, facecolor="#eef5fb", edgecolor=BLUE, zorder=2))
        ax.text(x, y, str(i), ha="center", va="center", fontsize=10, color=BLUE, zorder=3)
    for name, (x, y, text) in leaves.items():
        ax.add_patch(Rectangle((x - 0.75, y - 0.35), 1.5, 0.7, facecolor="#fbf3e0",
                               edgecolor=GOLD, zorder=2))
        ax.text(x, y, text, ha="center", va="center", fontsize=7.5, zorder=3)
    ax.text(16, 9.4, "interior nodes: circles, numbered by\ntheir place in the array "
            "(depth first)\nleaves: runs of triangles in Bvh::triangles,\nheld by their "
            "parent (count > 0)", fontsize=8.5, color=GREY, va="top")

    # The array below: each node holds both children's boxes, first[] and count[].
    y0 = 0.9
    w = 4.6
    for i in range(4):
        x = 1 + i * (w + 0.4)
        ax.add_patch(Rectangle((x, y0), w, 1.5, facecolor="#eef5fb", edgecolor=BLUE))
        ax.text(x + 0.1, y0 + 1.72, f"node {i}  (64 bytes)", fontsize=8.5, color=BLUE)
        fields = [("box[0]", 0.0, 1.25), ("box[1]", 1.25, 1.25), ("first", 2.5, 1.05),
                  ("count", 3.55, 1.05)]
        for label, dx, fw in fields:
            ax.add_patch(Rectangle((x + dx, y0), fw, 1.5, facecolor="none", edgecolor=BLUE,
                                   linewidth=0.6))
            ax.text(x + dx + fw / 2, y0 + 1.2, label, ha="center", fontsize=7, color=GREY)
    contents = {0: ("1, 3", "0, 0"), 1: ("2, 7", "0, 2"), 2: ("0, 4", "4, 3"),
                3: ("9, 13", "4, 2")}
    for i, (first, count) in contents.items():
        x = 1 + i * (w + 0.4)
        ax.text(x + 3.02, y0 + 0.5, first, ha="center", fontsize=7.5, family="monospace")
        ax.text(x + 4.07, y0 + 0.5, count, ha="center", fontsize=7.5, family="monospace")
        ax.text(x + 0.62, y0 + 0.5, "lo, hi", ha="center", fontsize=7, color=GREY)
        ax.text(x + 1.87, y0 + 0.5, "lo, hi", ha="center", fontsize=7, color=GREY)
    # first[0] of an interior child is always the next node; first[1] jumps over a subtree.
    arrow(ax, (1 + w - 1.1, y0 - 0.05), (1 + w + 0.4 + 0.5, y0 - 0.05), GREEN, rad=0.5)
    arrow(ax, (1 + w - 0.9, y0 - 0.1), (1 + 3 * (w + 0.4) + 0.5, y0 - 0.1), RED, rad=0.25)
    arrow(ax, (1 + 2 * w + 0.4 - 1.1, y0 - 0.05), (1 + 2 * (w + 0.4) + 0.5, y0 - 0.05), GREEN,
          rad=0.5)
    ax.text(11, -0.8, "green: child 0 is always the very next node    red: child 1 at the offset "
            "first[1], after child 0's whole subtree    count 0: interior child, n > 0: a leaf "
            "of n triangles starting at first", ha="center", fontsize=7.5, color=GREY)
    save(fig, out / "07_node_array.svg")


def slab_cases(out):
    cases = [
        ("ordinary ray", (0.3, 0.2), (1.0, 0.55), "near = (lo-o)/d, far = (hi-o)/d\n"
         "interval [near, far]", GREEN),
        ("d.x = 0, o inside", (0.5, 0.1), (0.0, 1.0), "near = -inf, far = +inf\n"
         "the axis does not constrain", GREEN),
        ("d.x = 0, o outside", (1.3, 0.1), (0.0, 1.0), "near, far both +inf (or -inf)\n"
         "missed, as it must be", GREEN),
        ("d.x = 0, o on a plane", (1.0, 0.1), (0.0, 1.0), "0 × inf = NaN: ignored by\n"
         "max/min_ignoring_nan: entered", GREEN),
        ("d.x = -0.0, planes by d < 0", (0.5, 0.1), (0.0, 1.0), "1/d = -inf, near = +inf,\n"
         "far = -inf: the box is missed", RED),
        ("d.x = -0.0, by sign of 1/d", (0.5, 0.1), (0.0, 1.0), "near = -inf, far = +inf\n"
         "as for +0.0: entered", GREEN),
    ]
    fig, axes = plt.subplots(1, len(cases), figsize=(13, 3.4))
    for ax, (title, o, d, text, colour) in zip(axes, cases):
        ax.set_xlim(-0.2, 1.6)
        ax.set_ylim(-0.1, 1.25)
        ax.set_aspect("equal")
        ax.axis("off")
        ax.add_patch(Rectangle((0.25, -0.05), 0.75, 1.2, facecolor="#eef5fb", edgecolor="none"))
        for x, label in ((0.25, "lo"), (1.0, "hi")):
            ax.plot([x, x], [-0.05, 1.15], color=BLUE, linewidth=1)
            ax.text(x, 1.17, label, ha="center", fontsize=7.5, color=BLUE)
        ax.plot(*o, "o", color=colour, markersize=4)
        ax.add_patch(FancyArrowPatch(o, (o[0] + 0.9 * d[0], o[1] + 0.9 * d[1]),
                                     arrowstyle="-|>", mutation_scale=10, color=colour))
        ax.set_title(title, fontsize=8.5)
        ax.text(0.7, -0.16, text, ha="center", va="top", fontsize=7.3, color=colour)
    fig.suptitle("The slab test on the x axis: the slab lo ≤ x ≤ hi, a ray o + t d", fontsize=10)
    save(fig, out / "07_slab_cases.svg")


def spatial_split(out):
    # Two long thin triangles side by side along the node's diagonal. An object split gives each
    # child one triangle and that triangle's box: both boxes are nearly the whole node. A spatial
    # split cuts the node at x = 5 and gives each child the parts of both triangles on its side;
    # its box holds the clipped parts, not the triangles' whole boxes.
    triangles = [[(0.2, 0.2), (9.8, 5.4), (9.8, 5.9)], [(0.2, 0.7), (0.2, 1.3), (9.8, 6.3)]]
    cut = 5.0

    def clipped(triangle, lo, hi):
        points = [p for p in triangle if lo <= p[0] <= hi]
        for i in range(3):
            a, b = triangle[i], triangle[(i + 1) % 3]
            for plane in (lo, hi):
                if min(a[0], b[0]) < plane < max(a[0], b[0]):
                    s = (plane - a[0]) / (b[0] - a[0])
                    points.append((plane, a[1] + (b[1] - a[1]) * s))
        return points

    def box(points):
        xs, ys = [p[0] for p in points], [p[1] for p in points]
        return (min(xs), min(ys)), max(xs) - min(xs), max(ys) - min(ys)

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    for ax, title in zip(axes, ["object split: one triangle per child",
                                "spatial split at x = 5: both triangles in both children"]):
        ax.set_xlim(-0.3, 10.3)
        ax.set_ylim(-0.7, 7.0)
        ax.set_aspect("equal")
        ax.axis("off")
        ax.set_title(title, fontsize=10)
        ax.add_patch(Rectangle((0.0, 0.0), 10.0, 6.5, fill=False, edgecolor=GREY, linewidth=1))
        for triangle in triangles:
            ax.add_patch(plt.Polygon(triangle, closed=True, facecolor="#eef5fb",
                                     edgecolor=BLUE, linewidth=1))
    left, right = axes
    for colour, triangle in zip([GOLD, GREEN], triangles):
        left.add_patch(Rectangle(*box(triangle), fill=False, edgecolor=colour, linewidth=1.6,
                                 linestyle="--"))
    left.text(5.0, -0.5, "the children's boxes overlap almost everywhere", ha="center",
              fontsize=8.5, color=RED)
    right.plot([cut, cut], [-0.2, 6.7], color=RED, linewidth=1.2)
    for colour, (lo, hi) in zip([GOLD, GREEN], [(-1e9, cut), (cut, 1e9)]):
        parts = [p for triangle in triangles for p in clipped(triangle, lo, hi)]
        right.add_patch(Rectangle(*box(parts), fill=False, edgecolor=colour, linewidth=1.6,
                                  linestyle="--"))
    right.text(5.0, -0.5, "each child's box holds the clipped parts on its side", ha="center",
               fontsize=8.5, color=GREEN)
    save(fig, out / "07_spatial_split.svg")


def main():
    out = Path(sys.argv[1] if len(sys.argv) > 1 else "book/images")
    plt.rcParams.update({"svg.hashsalt": "rt-course-ch07", "font.family": "DejaVu Sans"})
    node_array(out)
    slab_cases(out)
    spatial_split(out)


if __name__ == "__main__":
    main()
