#!/usr/bin/env python3
"""Chapter 06's diagrams (book/images/06_*.svg): Lambert's cosine law, and where a shadow ray
starts: the hit point's rounding, chapter 03's offset along the geometric normal, and the
shadow terminator with Hanika's lift.

  tools/diagrams/ch06.py [OUT_DIR]     (default: book/images)
"""
import math
import sys
from pathlib import Path

import matplotlib

matplotlib.use("svg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import Arc, FancyArrowPatch, Polygon  # noqa: E402

BLUE, GREY, RED, GOLD = "#2a7ab0", "#555555", "#c0392b", "#d4a017"


def arrow(ax, start, end, colour, width=1.3, style="-|>"):
    ax.add_patch(FancyArrowPatch(start, end, arrowstyle=style, mutation_scale=12, color=colour,
                                 linewidth=width))


def save(fig, path):
    fig.savefig(path, format="svg", metadata={"Date": None}, bbox_inches="tight")


def lambert(out):
    fig, axes = plt.subplots(1, 2, figsize=(10, 3.8))
    for ax, theta_deg in zip(axes, (0, 60)):
        ax.set_xlim(-3, 3)
        ax.set_ylim(-0.6, 3.6)
        ax.set_aspect("equal")
        ax.axis("off")
        theta = math.radians(theta_deg)
        ax.plot([-2.8, 2.8], [0, 0], color=GREY, linewidth=2)  # the surface
        arrow(ax, (0, 0), (0, 1.2), BLUE)
        ax.text(0.12, 1.25, "n", color=BLUE, fontsize=11)
        l = (-math.sin(theta), math.cos(theta))  # towards the light
        half = 0.5  # half the beam's width A
        spread = half / math.cos(theta)
        # The beam: parallel rays of width A arriving along -l, covering A / cos(theta).
        for s in (-half, 0, half):
            foot = (s / math.cos(theta), 0)
            start = (foot[0] + 3.0 * l[0], foot[1] + 3.0 * l[1])
            arrow(ax, start, foot, GOLD, 1.0)
        starts = [(s / math.cos(theta) + 3.0 * l[0], 3.0 * l[1]) for s in (-half, half)]
        beam = [starts[0], starts[1], (spread, 0), (-spread, 0)]
        ax.add_patch(Polygon(beam, closed=True, facecolor=GOLD, alpha=0.15, edgecolor="none"))
        ax.plot([-spread, spread], [0.0, 0.0], color=RED, linewidth=4, solid_capstyle="butt")
        if theta_deg:
            ax.add_patch(Arc((0, 0), 1.6, 1.6, theta1=90, theta2=90 + theta_deg, color=GREY))
            ax.text(-0.55, 0.95, "θ", fontsize=11, color=GREY)
            arrow(ax, (0, 0), (1.2 * l[0], 1.2 * l[1]), GOLD)
            ax.text(1.2 * l[0] - 0.25, 1.2 * l[1], "l", color=GOLD, fontsize=11)
        ax.text(0, -0.45, f"θ = {theta_deg}°: lit width A / cos θ = {1 / math.cos(theta):.0f} A,"
                f" irradiance × cos θ = {math.cos(theta):.1f}", ha="center", fontsize=9,
                color=RED)
    fig.suptitle("Lambert's cosine law: the same beam (width A) spreads over A / cos θ, so "
                 "each unit of surface gets cos θ = n · l of it", fontsize=10)
    save(fig, out / "06_lambert_cosine.svg")


def shadow_offset(out):
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    # Left: the hit point lies a rounding error off its triangle; the offset moves the origin
    # out along the geometric normal, on the viewer's side.
    ax = axes[0]
    ax.set_xlim(-3, 3)
    ax.set_ylim(-1.2, 3)
    ax.set_aspect("equal")
    ax.axis("off")
    ax.fill_between([-2.8, 2.8], [-1.0, -1.0], [0, 0], color="#eeeeee")
    ax.plot([-2.8, 2.8], [0, 0], color=GREY, linewidth=2)
    ax.text(2.75, -0.35, "triangle", ha="right", fontsize=8.5, color=GREY)
    p = (-0.4, -0.12)
    ax.plot(*p, "o", color=RED, markersize=5)
    ax.text(p[0] - 0.15, p[1] - 0.35, "p, rounded: just below", fontsize=8.5, color=RED,
            ha="center")
    arrow(ax, (-2.6, 2.6), (p[0], p[1] + 0.05), GREY, 1.0)
    ax.text(-2.55, 2.7, "camera ray", fontsize=8.5, color=GREY)
    arrow(ax, p, (0.6, 1.6), RED, 1.0)
    ax.plot([p[0] + 0.08], [p[1] + 0.13], "x", color=RED, markersize=8)
    ax.text(0.65, 1.6, "shadow ray from p:\nhits its own triangle\nat t ≈ 0 (acne)", fontsize=8.5,
            color=RED)
    o = (1.2, 0.55)
    base = (1.2, 0.0)
    arrow(ax, base, o, BLUE, 1.2)
    ax.plot(*o, "o", color=BLUE, markersize=5)
    ax.text(1.32, 0.22, "offset along the\ngeometric normal,\nscaled by |p|\n(chapter 03)",
            fontsize=8.5, color=BLUE)
    arrow(ax, o, (2.4, 2.6), BLUE, 1.0)
    ax.text(2.35, 2.7, "to the light", fontsize=8.5, color=BLUE, ha="right")
    ax.set_title("acne, and chapter 03's offset", fontsize=10)

    # Right: the terminator. Three facets of a coarse circle under the smooth surface; the
    # light comes from the left, just below the top facet's plane. Near the top facet's left
    # end the smooth normal still faces the light, but a shadow ray from the facet enters the
    # solid and leaves through the left facet: blocked. Lifted to the smooth surface, it clears.
    ax = axes[1]
    ax.set_xlim(-2.6, 1.6)
    ax.set_ylim(0.4, 2.9)
    ax.set_aspect("equal")
    ax.axis("off")
    r = 2.4
    point = lambda deg, radius=r: (radius * math.cos(math.radians(deg)),  # noqa: E731
                                   radius * math.sin(math.radians(deg)))
    arc = [point(40 + t) for t in range(0, 121)]
    ax.plot([c[0] for c in arc], [c[1] for c in arc], color=BLUE, linestyle="--", linewidth=1)
    ax.text(0.95, 2.3, "smooth surface the\nvertex normals describe", fontsize=8.5,
            color=BLUE)
    verts = [point(a) for a in (150, 110, 70, 30)]
    ax.plot([v[0] for v in verts], [v[1] for v in verts], color=GREY, linewidth=2,
            marker="o", markersize=4)
    ax.text(1.35, 1.5, "flat facets", fontsize=8.5, color=GREY)
    light = (-1.0 / math.hypot(1.0, 0.1), -0.1 / math.hypot(1.0, 0.1))
    x = -0.26 * r
    p = (x, point(70)[1])  # on the top facet, near its left end
    # Where the ray from p leaves through the left facet (verts[0] to verts[1]).
    (ax0, ay0), (bx, by) = verts[0], verts[1]
    dx, dy = bx - ax0, by - ay0
    det = light[0] * (-dy) - light[1] * (-dx)
    t = ((ax0 - p[0]) * (-dy) - (ay0 - p[1]) * (-dx)) / det
    block = (p[0] + t * light[0], p[1] + t * light[1])
    ax.plot(*p, "o", color=RED, markersize=5)
    ax.plot([p[0], block[0]], [p[1], block[1]], color=RED, linewidth=1.2)
    ax.plot(*block, "x", color=RED, markersize=9, markeredgewidth=2)
    ax.text(-1.3, 1.45, "from the facet: into the\nsolid, blocked by the\nneighbour facet",
            fontsize=8.5, color=RED)
    lifted = (x, math.sqrt(r * r - x * x))
    ax.plot(*lifted, "o", color=BLUE, markersize=5)
    arrow(ax, lifted, (lifted[0] + 2.1 * light[0], lifted[1] + 2.1 * light[1]), BLUE, 1.0)
    ax.text(-2.55, 2.75, "lifted (Hanika 2021): clears it, to the light", fontsize=8.5,
            color=BLUE)
    ax.set_title("the shadow terminator, and the lift", fontsize=10)
    save(fig, out / "06_shadow_offset.svg")


def main():
    out = Path(sys.argv[1] if len(sys.argv) > 1 else "book/images")
    plt.rcParams.update({"svg.hashsalt": "rt-course-ch06", "font.family": "DejaVu Sans"})
    lambert(out)
    shadow_offset(out)


if __name__ == "__main__":
    main()
