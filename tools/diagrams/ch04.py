#!/usr/bin/env python3
"""Chapter 04's diagram: the watertight test's change of frame. Translate the vertices by the
ray's origin, permute the axes so that z is the direction's largest component, shear so that
the ray becomes the z axis, then look down the ray and read three edge functions
(book/images/04_watertight_frame.svg).

  tools/diagrams/ch04.py [OUT_DIR]     (default: book/images)
"""
import sys
from pathlib import Path

import matplotlib

matplotlib.use("svg")
matplotlib.rcParams["svg.hashsalt"] = "rt-course"  # the same file on every run
matplotlib.rcParams["svg.fonttype"] = "none"  # text stays text
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import FancyArrowPatch, Polygon  # noqa: E402

BLUE, GREEN, GREY, RED, ORANGE = "#2a7ab0", "#2e8b57", "#555555", "#c0392b", "#e08a1e"

# A triangle and a ray in the x-z plane (the side view of panels 1-3): z is the direction's
# largest component after the permutation.
TRIANGLE = [(2.6, 3.6), (4.4, 4.4), (3.4, 5.4)]
ORIGIN, DIRECTION = (1.2, 0.8), (0.55, 1.0)


def arrow(ax, start, end, colour, width=1.4):
    ax.add_patch(FancyArrowPatch(start, end, arrowstyle="-|>", mutation_scale=11,
                                 color=colour, linewidth=width, shrinkA=0, shrinkB=0))


def side_view(ax, title, triangle, origin, direction, axes_at):
    ax.set_title(title, fontsize=9.5, color=GREY, loc="left")
    ax.set_xlim(-1.0, 6.0)
    ax.set_ylim(-0.6, 6.4)
    ax.set_aspect("equal")
    ax.axis("off")
    ox, oz = axes_at
    arrow(ax, (ox, oz), (ox + 2.2, oz), GREY, 0.8)
    arrow(ax, (ox, oz), (ox, oz + 2.2), GREY, 0.8)
    ax.text(ox + 2.3, oz - 0.1, "x", fontsize=9, color=GREY)
    ax.text(ox - 0.1, oz + 2.35, "z", fontsize=9, color=GREY)
    ax.add_patch(Polygon(triangle, closed=True, facecolor="#eef4fa", edgecolor=BLUE,
                         linewidth=1.4))
    end = (origin[0] + 5.5 * direction[0], origin[1] + 5.5 * direction[1])
    ax.plot([origin[0], end[0]], [origin[1], end[1]], color=RED, linestyle=(0, (4, 3)),
            linewidth=1.0)
    arrow(ax, origin, (origin[0] + 1.2 * direction[0], origin[1] + 1.2 * direction[1]), RED)
    ax.plot(*origin, "o", color=RED, markersize=4)


def main():
    out = Path(sys.argv[1] if len(sys.argv) > 1 else "book/images")
    fig, axes = plt.subplots(1, 4, figsize=(13, 4.2))

    side_view(axes[0], "1. the ray and a triangle", TRIANGLE, ORIGIN, DIRECTION, (-0.6, -0.3))
    axes[0].text(ORIGIN[0] + 0.2, ORIGIN[1] - 0.35, "o", fontsize=10, color=RED)
    axes[0].text(ORIGIN[0] + 0.75, ORIGIN[1] + 0.6, "d", fontsize=10, color=RED)

    moved = [(x - ORIGIN[0], z - ORIGIN[1]) for x, z in TRIANGLE]
    side_view(axes[1], "2. translate by -o; permute so\n    that |d_z| is the largest",
              moved, (0, 0), DIRECTION, (0, 0))
    axes[1].text(-0.9, 6.1, "a = v0 - o\nb = v1 - o\nc = v2 - o", fontsize=8.5, color=GREY,
                 va="top")

    shear = DIRECTION[0] / DIRECTION[1]
    sheared = [(x - shear * z, z) for x, z in moved]
    side_view(axes[2], "3. shear: x -= (d_x / d_z) z,\n    y -= (d_y / d_z) z", sheared, (0, 0),
              (0.0, 1.0), (0, 0))
    axes[2].text(2.3, 4.8, "the ray is\nthe z axis", fontsize=8.5, color=RED, va="top")

    # 4. Looking down the ray: two triangles sharing an edge, the ray a point at the origin.
    ax = axes[3]
    ax.set_title("4. look down the ray: three\n    edge functions, one sign", fontsize=9.5,
                 color=GREY, loc="left")
    ax.set_xlim(-3.0, 3.4)
    ax.set_ylim(-2.8, 3.6)
    ax.set_aspect("equal")
    ax.axis("off")
    a, b, c, e = (-2.2, -1.6), (2.4, -1.2), (0.4, 2.6), (-2.0, 2.4)
    ax.add_patch(Polygon([a, b, c], closed=True, facecolor="#eef4fa", edgecolor=BLUE,
                         linewidth=1.4))
    ax.add_patch(Polygon([a, c, e], closed=True, facecolor="#f6f6f6", edgecolor=GREY,
                         linewidth=1.0))
    ax.plot(0, 0, "o", color=RED, markersize=5)
    ax.text(0.15, -0.35, "ray", fontsize=8.5, color=RED)
    for p, name, dx, dy in ((a, "a", -0.35, -0.3), (b, "b", 0.15, -0.3), (c, "c", 0.1, 0.15),
                            (e, "e", -0.3, 0.15)):
        ax.text(p[0] + dx, p[1] + dy, name, fontsize=10, color=BLUE)
    ax.text(0.9, -1.85, "W > 0 (edge a b)", fontsize=8, color=GREEN, ha="center")
    ax.text(2.05, 0.9, "U > 0\n(edge b c)", fontsize=8, color=GREEN)
    ax.text(-0.45, 0.35, "V > 0", fontsize=8, color=GREEN, ha="center", rotation=58)
    ax.text(-2.9, 3.35, "edge c a, seen from the grey triangle: -V", fontsize=8, color=GREY)
    ax.text(-2.9, -2.65, "t = (U a_z + V b_z + W c_z) / (U + V + W) / d_z", fontsize=8,
            color=GREY)

    out.mkdir(parents=True, exist_ok=True)
    fig.savefig(out / "04_watertight_frame.svg", bbox_inches="tight", metadata={"Date": None})


if __name__ == "__main__":
    main()
