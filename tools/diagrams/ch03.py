#!/usr/bin/env python3
"""Chapter 03's diagram: the geometry behind the stable ray/sphere test: f, beta, l and the
half chord, and the two ways of computing the discriminant (book/images/03_stable_quadratic.svg).

  tools/diagrams/ch03.py [OUT_DIR]     (default: book/images)
"""
import math
import sys
from pathlib import Path

import matplotlib

matplotlib.use("svg")
matplotlib.rcParams["svg.hashsalt"] = "rt-course"  # the same file on every run
matplotlib.rcParams["svg.fonttype"] = "none"  # text stays text
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import Circle, FancyArrowPatch  # noqa: E402

BLUE, GREEN, GREY, RED, ORANGE = "#2a7ab0", "#2e8b57", "#555555", "#c0392b", "#e08a1e"


def arrow(ax, start, end, colour, width=1.4, style="-|>"):
    ax.add_patch(FancyArrowPatch(start, end, arrowstyle=style, mutation_scale=12, color=colour,
                                 linewidth=width, shrinkA=0, shrinkB=0))


def main():
    out = Path(sys.argv[1] if len(sys.argv) > 1 else "book/images")
    fig, ax = plt.subplots(figsize=(10, 4.8))
    ax.set_xlim(-6.3, 6.3)
    ax.set_ylim(-3.2, 4.1)
    ax.set_aspect("equal")
    ax.axis("off")

    centre, radius = (2.2, 0.0), 1.8
    origin, angle = (-5.2, -2.0), math.radians(23.0)
    d = (math.cos(angle), math.sin(angle))  # a unit direction: a = d.d = 1
    f = (origin[0] - centre[0], origin[1] - centre[1])
    beta = -(f[0] * d[0] + f[1] * d[1])
    m = (origin[0] + beta * d[0], origin[1] + beta * d[1])  # nearest point of the line
    l_vec = (m[0] - centre[0], m[1] - centre[1])
    l_len = math.hypot(*l_vec)
    half_chord = math.sqrt(radius * radius - l_len * l_len)
    near = (m[0] - half_chord * d[0], m[1] - half_chord * d[1])
    far = (m[0] + half_chord * d[0], m[1] + half_chord * d[1])

    ax.add_patch(Circle(centre, radius, facecolor="#eef4fa", edgecolor=BLUE, linewidth=1.6))
    ax.plot(*centre, "o", color=BLUE, markersize=4)
    ax.text(centre[0] + 0.15, centre[1] + 0.05, "c", fontsize=12, color=BLUE)
    arrow(ax, centre, (centre[0] + radius * 0.8, centre[1] - radius * 0.6), BLUE, 1.0, "-")
    ax.text(centre[0] + 0.75, centre[1] - 0.3, "r", fontsize=11, color=BLUE)

    # The ray and its line.
    end = (origin[0] + 11.0 * d[0], origin[1] + 11.0 * d[1])
    ax.plot([origin[0], end[0]], [origin[1], end[1]], color=GREY, linewidth=1.0,
            linestyle=(0, (4, 3)))
    arrow(ax, origin, (origin[0] + 1.3 * d[0], origin[1] + 1.3 * d[1]), GREY, 1.8)
    ax.plot(*origin, "o", color=GREY, markersize=4)
    ax.text(origin[0] - 0.45, origin[1] - 0.1, "o", fontsize=12, color=GREY)
    ax.text(origin[0] + 0.75, origin[1] - 0.05, "d", fontsize=11, color=GREY)

    # f = o - c, beta along the ray, l from the centre to the nearest point.
    arrow(ax, centre, origin, ORANGE, 1.0)
    ax.text(-1.2, -1.45, "f = o - c", fontsize=10, color=ORANGE)
    arrow(ax, centre, m, RED, 1.4)
    ax.text((centre[0] + m[0]) / 2 - 0.35, (centre[1] + m[1]) / 2, "l", fontsize=12,
            color=RED)
    ax.plot(*m, "o", color=RED, markersize=4)
    for (a, b), text, lift in (((origin, m), "beta = -f.d  (when |d| = 1)", 0.95),):
        ax.annotate("", xy=(b[0] - 0.35 * d[1], b[1] + 0.35 * d[0]),
                    xytext=(a[0] - 0.35 * d[1], a[1] + 0.35 * d[0]),
                    arrowprops=dict(arrowstyle="<->", color=GREEN, lw=1.0))
        ax.text((a[0] + b[0]) / 2 - lift * d[1] - 0.4, (a[1] + b[1]) / 2 + lift * d[0] - 0.05,
                text, fontsize=9.5, color=GREEN, ha="center", rotation=math.degrees(angle))
    # The half chord on each side of m: the square root of the discriminant.
    for p, label, dx, align in ((near, "t1 = beta - h", -0.25, "right"),
                                (far, "t2 = beta + h", 0.2, "left")):
        ax.plot(*p, "s", color=RED, markersize=5)
        ax.text(p[0] + dx, p[1] + 0.2, label, fontsize=9, color=RED, ha=align)
    ax.annotate("", xy=(m[0] + 0.3 * d[1], m[1] - 0.3 * d[0]),
                xytext=(far[0] + 0.3 * d[1], far[1] - 0.3 * d[0]),
                arrowprops=dict(arrowstyle="<->", color=RED, lw=1.0))
    ax.text((m[0] + far[0]) / 2 + 0.3, (m[1] + far[1]) / 2 - 0.5, "h", fontsize=11,
            color=RED)

    ax.text(-6.2, 3.85, "h\u00b2 = r\u00b2 - |l|\u00b2 = beta\u00b2 - c',   c' = |f|\u00b2 - r\u00b2",
            fontsize=10.5, color=GREY)
    ax.text(-6.2, 3.35, "far from a small sphere: l is short, so r\u00b2 - |l|\u00b2 keeps its "
            "digits; beta\u00b2 and c' are huge and cancel", fontsize=9, color=GREY)
    ax.text(-6.2, 2.95, "close to a huge sphere: c' is small (compensated), so beta\u00b2 - c' "
            "keeps its digits; |l|\u00b2 and r\u00b2 are huge and cancel", fontsize=9,
            color=GREY)
    ax.text(-6.2, -3.05, "the roots without cancellation: q = beta + sign(beta) h,  "
            "t = q (the far root here) and t = c' / q (the near one)", fontsize=9, color=GREY)

    out.mkdir(parents=True, exist_ok=True)
    fig.savefig(out / "03_stable_quadratic.svg", bbox_inches="tight", metadata={"Date": None})


if __name__ == "__main__":
    main()
