#!/usr/bin/env python3
"""Chapter 11's diagrams (book/images/11_*.svg): the change of measure that turns next-event
estimation's density per unit area of an emitter into a density per solid angle at the shaded
point; the power heuristic's weights of the two strategies against the size of the light,
from the formulas of path_sampling.h; the three ways of running paths on a GPU (the
megakernel, the wavefront, persistent threads) as timelines of a few lanes; and two pictures of
radiometry: a patch's solid angle and its shadow on the disc under the hemisphere (the projected
solid angle, whose whole is pi), and irradiance's cosine (one beam over a surface turned away).

  tools/diagrams/ch11.py [OUT_DIR]     (default: book/images)
"""
import math
import sys
from pathlib import Path

import matplotlib

matplotlib.use("svg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.patches import Arc, FancyArrowPatch, Polygon, Rectangle  # noqa: E402

BLUE, GREY, RED, GOLD, GREEN = "#2a7ab0", "#555555", "#c0392b", "#d4a017", "#2e8b57"
IDLE = "#e4e4e4"


def arrow(ax, start, end, colour, width=1.3, style="-|>", dashed=False):
    ax.add_patch(FancyArrowPatch(start, end, arrowstyle=style, mutation_scale=11, color=colour,
                                 linewidth=width, linestyle="--" if dashed else "-"))


def save(fig, path):
    fig.savefig(path, format="svg", metadata={"Date": None}, bbox_inches="tight")
    plt.close(fig)


def unit(v):
    return v / np.linalg.norm(v)


def degrees_of(v):
    return math.degrees(math.atan2(v[1], v[0]))


# ------------------------------------------------------------------------------------------
# From area to solid angle.

def angle_arc(ax, centre, diameter, first, second, colour, width=1.0):
    """The arc from direction `first` to direction `second` the short way round."""
    a, b = degrees_of(first), degrees_of(second)
    if (b - a) % 360 > 180:
        a, b = b, a
    ax.add_patch(Arc(tuple(centre), diameter, diameter, theta1=a, theta2=b, color=colour,
                     linewidth=width))


def area_to_solid_angle(out):
    fig, ax = plt.subplots(figsize=(10, 5.4))
    ax.set_xlim(-1.6, 8.4)
    ax.set_ylim(-0.8, 5.0)
    ax.set_aspect("equal")
    ax.axis("off")
    p = np.array([0.0, 0.0])
    q = np.array([5.4, 2.6])  # the point the light table picked
    to_p, to_q = unit(p - q), unit(q - p)
    # The emitter: a flat piece whose front normal makes theta_q with the direction to p.
    theta_q = math.radians(35)
    rotation = np.array([[math.cos(theta_q), math.sin(theta_q)],
                         [-math.sin(theta_q), math.cos(theta_q)]])
    n_q = rotation @ to_p
    along = np.array([-n_q[1], n_q[0]])  # the emitter's own direction, across its normal
    ax.plot(*zip(q - 2.0 * along, q + 2.0 * along), color=GOLD, linewidth=2.5,
            solid_capstyle="butt")
    for s in np.linspace(-1.8, 1.8, 10):  # hatching behind the emitter: its back
        base = q + s * along
        ax.plot(*zip(base, base - 0.2 * n_q + 0.12 * along), color=GOLD, linewidth=0.8)
    top = max(q + 2.0 * along, q - 2.0 * along, key=lambda end: end[1])
    ax.text(top[0] + 0.3, top[1] - 0.1, "emitter, emitting\nfrom its front", fontsize=9,
            color=GOLD, va="top")
    half = 0.45  # half of the patch dA
    a, b = q - half * along, q + half * along
    ax.plot(*zip(a, b), color=RED, linewidth=5, solid_capstyle="butt")
    upper = max(a, b, key=lambda end: end[1])
    ax.text(*(upper + np.array([0.25, -0.1])), "dA", fontsize=12, color=RED)
    ax.plot(*q, "o", color=GOLD, markersize=4)
    ax.text(*(q + np.array([0.3, -0.2])), "q", fontsize=11, color=GOLD)
    # The surface at p and its normal.
    ax.add_patch(Polygon([(-1.4, 0), (2.2, 0), (2.2, -0.2), (-1.4, -0.2)], closed=True,
                         facecolor="#eeeeee", edgecolor="none"))
    ax.plot([-1.4, 2.2], [0, 0], color=GREY, linewidth=2)
    ax.plot(*p, "o", color=BLUE, markersize=5)
    ax.text(-0.15, 0.1, "p, the\nshaded point", fontsize=9.5, color=BLUE, ha="right",
            va="bottom")
    arrow(ax, tuple(p), (0.0, 1.7), BLUE)
    ax.text(0.1, 1.62, "n", fontsize=11, color=BLUE)
    angle_arc(ax, p, 1.6, to_q, np.array([0.0, 1.0]), BLUE)
    ax.text(0.38, 0.9, "θ", fontsize=11, color=BLUE)
    # The cone from p through the patch, and the piece of the unit circle it cuts: d(omega).
    for corner in (a, b):
        ax.plot(*zip(p, corner), color=RED, linewidth=0.9)
    ax.add_patch(Polygon([tuple(p), tuple(a), tuple(b)], closed=True, facecolor=RED,
                         alpha=0.08, edgecolor="none"))
    radius = 2.0
    ax.add_patch(Arc(tuple(p), 2 * radius, 2 * radius, theta1=3, theta2=87, color=GREY,
                     linewidth=0.7, linestyle=":"))
    angle_arc(ax, p, 2 * radius, a - p, b - p, RED, 3.5)
    ax.text(*(p + (radius + 0.12) * to_q + np.array([-0.15, 0.2])), "dω", fontsize=12,
            color=RED)
    ax.text(1.55, 1.55, "unit sphere\nround p", fontsize=8, color=GREY, ha="left")
    # The distance d, beside the direction.
    offset = 0.5 * np.array([to_q[1], -to_q[0]])
    arrow(ax, tuple(p + offset), tuple(q + offset), GREY, 0.9, style="<|-|>")
    for end in (p, q):
        ax.plot(*zip(end + 0.2 * offset, end + 1.2 * offset), color=GREY, linewidth=0.6)
    ax.text(*((p + q) / 2 + 1.6 * offset), "d", fontsize=12, color=GREY, ha="center",
            va="center")
    # The emitter's normal, the angle theta_q, and the patch as p sees it: dA cos(theta_q).
    arrow(ax, tuple(q), tuple(q + 1.5 * n_q), GOLD)
    ax.text(*(q + 1.55 * n_q + np.array([-0.55, 0.0])), "n_q", fontsize=11, color=GOLD)
    arrow(ax, tuple(q), tuple(q + 1.5 * to_p), GREY, 0.9, dashed=True)
    angle_arc(ax, q, 1.4, n_q, to_p, GOLD)
    middle = unit(n_q + to_p)
    ax.text(*(q + 0.95 * middle), "θq", fontsize=11, color=GOLD, ha="center", va="center")
    across = np.array([-to_q[1], to_q[0]])
    projected = half * math.cos(theta_q)
    ax.plot(*zip(q - projected * across, q + projected * across), color=RED, linewidth=1.6,
            linestyle=(0, (3, 2)))
    ax.annotate("dA cos θq: the patch\nas p sees it", xy=tuple(q - 0.8 * projected * across),
                xytext=(5.2, 0.6), fontsize=9, color=RED,
                arrowprops={"arrowstyle": "->", "color": RED, "linewidth": 0.8})
    ax.text(-1.45, 4.9,
            "dω = cos θq dA / d²\n\n"
            "so a density per unit area of the emitter\n"
            "is a density per solid angle at p\n"
            "times d² / cos θq:\n"
            "pdf_light = (lum(Le) / power) · d² / cos θq",
            fontsize=9.5, color=GREY, va="top",
            bbox={"boxstyle": "round,pad=0.4", "facecolor": "white", "edgecolor": GREY,
                  "linewidth": 0.6})
    save(fig, out / "11_area_to_solid_angle.svg")


# ------------------------------------------------------------------------------------------
# The power heuristic's weights against the size of the light.

def power_heuristic(pdf_a, pdf_b):
    """path_sampling.h's power_heuristic (exponent 2)."""
    a, b = pdf_a * pdf_a, pdf_b * pdf_b
    return a / (a + b)


def rectangle_solid_angle(width, length, distance):
    """The solid angle of a width x length rectangle facing a point at `distance` below its
    centre."""
    return 4 * math.asin(width * length / math.sqrt((width ** 2 + 4 * distance ** 2) *
                                                    (length ** 2 + 4 * distance ** 2)))


def mis_weights(out):
    solid_angles = np.geomspace(1e-3, 2 * math.pi, 400)
    pdf_bsdf = 1 / math.pi  # cosine_density near the normal: cos / pi with cos ~ 1
    pdf_light = 1 / solid_angles  # a small light of uniform density over its solid angle
    light_weight = power_heuristic(pdf_light, pdf_bsdf)
    bsdf_weight = power_heuristic(pdf_bsdf, pdf_light)
    fig, ax = plt.subplots(figsize=(8.5, 4.4))
    ax.plot(solid_angles, light_weight, color=GOLD, linewidth=2,
            label="w(p_light, p_bsdf): the shadow ray's weight")
    ax.plot(solid_angles, bsdf_weight, color=BLUE, linewidth=2,
            label="w(p_bsdf, p_light): the bounce's weight")
    ax.plot(solid_angles, light_weight + bsdf_weight, color=GREY, linewidth=0.8,
            linestyle=":", label="their sum: 1 for every direction")
    ax.set_xscale("log")
    ax.set_xlim(solid_angles[0], solid_angles[-1])
    ax.set_ylim(-0.03, 1.08)
    ax.axvline(math.pi, color=GREY, linewidth=0.8, linestyle="--")
    ax.annotate("p_light = p_bsdf at a solid angle of π:\nthe bounce takes over beyond",
                xy=(math.pi, 0.5), xytext=(0.9, 0.42), fontsize=8.5, color=GREY, ha="right",
                va="center", arrowprops={"arrowstyle": "->", "color": GREY, "linewidth": 0.8})
    # The room's light (0.5 x 0.4 at 1.98) seen from the middle of the floor.
    room = rectangle_solid_angle(0.5, 0.4, 1.98)
    ax.plot([room], [power_heuristic(1 / room, pdf_bsdf)], "o", color=RED, markersize=5)
    ax.annotate(f"the room's light from the middle of the floor:\n{room:.3f} sr, "
                f"p_light = {1 / room:.0f} against 1/π = {pdf_bsdf:.2f}",
                xy=(room, power_heuristic(1 / room, pdf_bsdf)), xytext=(0.0016, 0.62),
                fontsize=8.5, color=RED,
                arrowprops={"arrowstyle": "->", "color": RED, "linewidth": 0.8})
    ax.set_xlabel("solid angle the light subtends at a diffuse point (steradians, log scale; "
                  "the right edge, 2π, is the whole hemisphere)")
    ax.set_ylabel("power-heuristic weight")
    ax.set_title("p_light = 1 / solid angle against p_bsdf = cos θ / π (cos θ ≈ 1): "
                 "NEE gets small lights, the bounce large ones", fontsize=9.5)
    ax.legend(fontsize=8, loc="lower left", bbox_to_anchor=(0.0, 0.08))
    save(fig, out / "11_mis_weights.svg")


# ------------------------------------------------------------------------------------------
# Megakernel, wavefront, persistent threads.

LANES_PER_WARP = 4  # 32 on the GPU; four are drawn
WARPS = 2  # warps the GPU holds at once, in this sketch
PATH_STEPS = [1, 4, 2, 1, 6, 1, 2, 3, 1, 1, 5, 2, 2, 3, 1, 1]  # bounces of paths 0 to 15
STAGES = (("extend", 0.45, BLUE), ("shade", 0.3, GREEN), ("connect", 0.25, GOLD))
GENERATE = 0.15  # a camera ray, against one bounce's 1
LAUNCH_GAP = 0.08  # between two kernels


def path_colour(path):
    return plt.get_cmap("tab20")(path % 20)


def lane_y(lane):
    """The lanes top down, a gap between warps."""
    warp = lane // LANES_PER_WARP
    return -(lane + 0.6 * warp)


def lane_axes(ax, title, end):
    lanes = LANES_PER_WARP * WARPS
    ax.set_xlim(-1.3, end)
    ax.axis("off")
    ax.text(-1.25, 0.6, title, fontsize=10, fontweight="bold", va="center")
    for lane in range(lanes):
        ax.text(-0.1, lane_y(lane), f"lane {lane % LANES_PER_WARP}", fontsize=7.5,
                color=GREY, ha="right", va="center")
    for warp in range(WARPS):
        first, last = warp * LANES_PER_WARP, (warp + 1) * LANES_PER_WARP - 1
        ax.text(-0.95, (lane_y(first) + lane_y(last)) / 2, f"warp\nslot {warp}", fontsize=8,
                color=GREY, ha="center", va="center")


def step_box(ax, lane, start, length, colour, text=None, hatch=None):
    y = lane_y(lane)
    ax.add_patch(Rectangle((start, y - 0.4), length, 0.8, facecolor=colour, edgecolor="white",
                           linewidth=0.8, hatch=hatch))
    if text is not None:
        ax.text(start + length / 2, y, text, fontsize=7, ha="center", va="center")


def megakernel_timeline(ax, end):
    """One thread per pixel; a warp holds its slot until its longest path ends, then the next
    warp of pixels takes the slot."""
    lane_axes(ax, "megakernel", end)
    slot_free = [0.0] * WARPS
    for warp in range(len(PATH_STEPS) // LANES_PER_WARP):
        slot = min(range(WARPS), key=lambda s: (slot_free[s], s))
        start = slot_free[slot]
        paths = range(warp * LANES_PER_WARP, (warp + 1) * LANES_PER_WARP)
        longest = max(PATH_STEPS[i] for i in paths)
        for within, path in enumerate(paths):
            lane = slot * LANES_PER_WARP + within
            for step in range(PATH_STEPS[path]):
                step_box(ax, lane, start + step, 1, path_colour(path), str(path))
            if PATH_STEPS[path] < longest:
                step_box(ax, lane, start + PATH_STEPS[path], longest - PATH_STEPS[path],
                         IDLE, hatch="///")
        slot_free[slot] = start + longest
    return max(slot_free)


def persistent_timeline(ax, end):
    """As many threads as the GPU holds; at every step a warp's lanes without a path take the
    next ones from the counter together."""
    lane_axes(ax, "persistent threads", end)
    lanes = LANES_PER_WARP * WARPS
    path_of = [None] * lanes
    left = [0] * lanes
    next_path, time = 0, 0
    while True:
        for lane in range(lanes):  # warp by warp, lane by lane: the ballot's order
            if left[lane] == 0 and next_path < len(PATH_STEPS):
                path_of[lane], left[lane] = next_path, PATH_STEPS[next_path]
                next_path += 1
        if not any(left):
            return time
        for lane in range(lanes):
            if left[lane] > 0:
                step_box(ax, lane, time, 1, path_colour(path_of[lane]), str(path_of[lane]))
                left[lane] -= 1
            else:
                step_box(ax, lane, time, 1, IDLE, hatch="///")
        time += 1


def wavefront_timeline(ax, end):
    """A kernel per stage over the queue of live paths: every thread launched has an item."""
    lane_axes(ax, "wavefront", end)
    lanes = LANES_PER_WARP * WARPS
    top, bottom = lane_y(0) + 0.4, lane_y(lanes - 1) - 0.4
    time = 0.0

    def kernel(name, items, cost, colour):
        nonlocal time
        width = items * cost / lanes
        ax.add_patch(Rectangle((time, bottom), width, top - bottom, facecolor=colour,
                               alpha=0.55, edgecolor="white", linewidth=0.8))
        if width >= 0.25:  # the narrow kernels of the last bounces go unnamed
            ax.text(time + width / 2, (top + bottom) / 2, name, rotation=90, fontsize=7.5,
                    ha="center", va="center")
        time += width + LAUNCH_GAP

    kernel("generate", len(PATH_STEPS), GENERATE, GREY)
    bounce = 0
    while True:
        live = sum(1 for steps in PATH_STEPS if steps > bounce)
        if live == 0:
            return time - LAUNCH_GAP
        start = time
        for name, cost, colour in STAGES:
            kernel(name, live, cost, colour)
        ax.text((start + time - LAUNCH_GAP) / 2, top + 0.2,
                f"{live} live" if bounce == 0 else str(live), fontsize=7.5, color=GREY,
                ha="center", va="bottom")
        bounce += 1


def kernel_shapes(out):
    end = 10.2
    fig, axes = plt.subplots(3, 1, figsize=(10, 9.4))
    finished = [megakernel_timeline(axes[0], end), persistent_timeline(axes[1], end),
                wavefront_timeline(axes[2], end)]
    notes = ("a warp holds its slot until its longest path ends: the lanes of shorter paths "
             "idle (hatched)",
             "a lane whose path ended takes the next path from a counter in global memory; "
             "when every path is taken,\nthe lanes whose paths ended idle until the last ends",
             "a kernel per stage (extend, shade, connect) over the queue of the live paths, "
             "their number above it:\nall its threads have work, and the queues shrink "
             "bounce by bounce; the paths' states go through memory")
    last = lane_y(LANES_PER_WARP * WARPS - 1)
    for ax, note, time in zip(axes, notes, finished):
        ax.text(0.0, last - 0.65, note, fontsize=8.5, color=GREY, va="top")
        ax.plot([time, time], [lane_y(0) + 0.55, last - 0.55], color=RED, linewidth=1.2)
        ax.text(time + 0.08, lane_y(0) + 0.45, "done", fontsize=8, color=RED, va="center")
        ax.set_ylim(last - 2.0, 0.85)
    arrow(axes[2], (0.0, last - 2.0), (end - 0.2, last - 2.0), GREY, 0.8)
    axes[2].text(end - 0.2, last - 1.93, "time", fontsize=8.5, color=GREY, ha="right",
                 va="bottom")
    axes[2].text(0.0, last - 2.2, "The same 16 paths (the numbers) in each; one box is one "
                 "bounce: trace, shade, shadow rays. Four lanes of a warp's 32 drawn; "
                 "schematic.", fontsize=8, color=GREY, va="top")
    axes[2].set_ylim(last - 2.6, 0.85)
    fig.subplots_adjust(hspace=0.12)
    save(fig, out / "11_kernel_shapes.svg")


# ------------------------------------------------------------------------------------------
# Solid angle and projected solid angle.

def solid_angle(out):
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.8),
                                      gridspec_kw={"width_ratios": [1.15, 1]})
    # Left: one patch at two distances, its footprint on the unit circle round p.
    ax = left
    ax.set_xlim(-1.3, 6.6)
    ax.set_ylim(-2.3, 2.6)
    ax.set_aspect("equal")
    ax.axis("off")
    p = np.array([0.0, 0.0])
    ax.add_patch(Arc((0, 0), 2, 2, theta1=0, theta2=360, color=GREY, linewidth=0.7,
                     linestyle=":"))
    ax.plot(*p, "o", color=BLUE, markersize=5)
    ax.text(-0.15, -0.15, "p", fontsize=11, color=BLUE, ha="right", va="top")
    ax.text(-0.75, 0.85, "unit circle\nround p", fontsize=8, color=GREY, ha="right")
    size = 0.9  # the patch's side
    for distance, colour, name in ((2.5, RED, "d"), (5.0, GOLD, "2d")):
        centre = np.array([distance, 0.0])
        a, b = centre + [0, -size / 2], centre + [0, size / 2]
        ax.plot(*zip(a, b), color=colour, linewidth=5, solid_capstyle="butt")
        for corner in (a, b):
            ax.plot(*zip(p, corner), color=colour, linewidth=0.8)
        ax.add_patch(Polygon([tuple(p), tuple(a), tuple(b)], closed=True, facecolor=colour,
                             alpha=0.08, edgecolor="none"))
        half = math.degrees(math.atan2(size / 2, distance))
        ax.add_patch(Arc((0, 0), 2, 2, theta1=-half, theta2=half, color=colour,
                         linewidth=4 if colour == RED else 2.5))
        ax.text(centre[0], b[1] + 0.15, f"A at {name}", fontsize=9.5, color=colour,
                ha="center", va="bottom")
    ax.text(0.95, 0.3, "ω", fontsize=11, color=RED)
    ax.text(1.02, -0.4, "ω/4", fontsize=9, color=GOLD)
    # The same patch turned by theta: narrower as p sees it.
    centre = np.array([2.5, -1.6])
    turn = math.radians(60)
    along = np.array([math.sin(turn), math.cos(turn)]) * size / 2
    ax.plot(*zip(centre - along, centre + along), color=GREEN, linewidth=4,
            solid_capstyle="butt")
    ax.plot([centre[0] + 0.45, centre[0] + 0.45],
            [centre[1] - size / 2 * math.cos(turn), centre[1] + size / 2 * math.cos(turn)],
            color=GREEN, linewidth=1.4, linestyle=(0, (3, 2)))
    ax.text(centre[0] + 0.6, centre[1], "turned by θ: it shows\nA cos θ to p", fontsize=8.5,
            color=GREEN, va="center")
    ax.text(-1.25, 2.55,
            "solid angle ω = A cos θ / d²  (steradians)\n"
            "twice as far: a quarter of the sky; the whole sphere: 4π",
            fontsize=9.5, color=GREY, va="top")
    # Right: the hemisphere above a point, in an oblique view, a patch dω on it and its shadow
    # straight down on the base disc: cos θ dω. The disc is the whole hemisphere's shadow.
    ax = right
    ax.set_xlim(-1.35, 1.45)
    ax.set_ylim(-0.75, 1.95)
    ax.set_aspect("equal")
    ax.axis("off")
    squash = 0.35  # the base circle seen from above the horizon

    def view(x, y, z):  # world (x, y, z), z up, to the page
        return np.array([x, z + squash * y])

    angles = np.linspace(0, 2 * math.pi, 200)
    base = np.array([view(math.cos(t), math.sin(t), 0) for t in angles])
    ax.add_patch(Polygon(base, closed=True, facecolor=BLUE, alpha=0.10, edgecolor=BLUE,
                         linewidth=1.0))
    dome = np.array([view(math.cos(t), 0, math.sin(t)) for t in np.linspace(0, math.pi, 100)])
    ax.plot(*dome.T, color=GREY, linewidth=1.0)
    ax.plot(*np.array([view(math.cos(t), math.sin(t), 0)
                       for t in np.linspace(0, math.pi, 100)]).T, color=GREY, linewidth=0.6,
            linestyle=":")
    ax.plot(*view(0, 0, 0), "o", color=BLUE, markersize=4)
    arrow(ax, tuple(view(0, 0, 0)), tuple(view(0, 0, 1.3)), BLUE)
    ax.text(*(view(0, 0, 1.3) + [0.06, -0.05]), "n", fontsize=11, color=BLUE)
    # The patch: theta in [45, 60] degrees, phi in [-50, -15] (front right of the dome).
    thetas, phis = np.radians([45, 60]), np.radians([-50, -15])
    edge = ([(thetas[0], f) for f in np.linspace(*phis, 12)] +
            [(t, phis[1]) for t in np.linspace(*thetas, 6)] +
            [(thetas[1], f) for f in np.linspace(*phis[::-1], 12)] +
            [(t, phis[0]) for t in np.linspace(*thetas[::-1], 6)])

    def on_sphere(t, f):
        return math.sin(t) * math.cos(f), math.sin(t) * math.sin(f), math.cos(t)

    patch = np.array([view(*on_sphere(t, f)) for t, f in edge])
    shadow = np.array([view(*on_sphere(t, f)[:2], 0) for t, f in edge])
    ax.add_patch(Polygon(patch, closed=True, facecolor=RED, alpha=0.7, edgecolor=RED))
    ax.add_patch(Polygon(shadow, closed=True, facecolor=RED, alpha=0.35, edgecolor=RED))
    middle = on_sphere(thetas.mean(), phis.mean())
    ax.plot(*zip(view(0, 0, 0), view(*middle)), color=RED, linewidth=0.8)
    for t, f in ((thetas[0], phis[0]), (thetas[1], phis[1]), (thetas[0], phis[1]),
                 (thetas[1], phis[0])):
        x, y, z = on_sphere(t, f)
        ax.plot(*zip(view(x, y, z), view(x, y, 0)), color=RED, linewidth=0.5, linestyle=":")
    ax.text(*(view(*middle) + [0.1, 0.02]), "dω", fontsize=11, color=RED)
    ax.annotate("its shadow on the disc:\ncos θ dω, the projected\nsolid angle",
                xy=tuple(view(*on_sphere(thetas.mean(), phis.mean())[:2], 0)),
                xytext=(-1.3, -0.72), fontsize=8.5, color=RED,
                arrowprops={"arrowstyle": "->", "color": RED, "linewidth": 0.8})
    ax.text(-1.3, 1.93,
            "the hemisphere: 2π sr; its shadow, the unit disc: area π\n"
            "∫ cos θ dω over the hemisphere = π",
            fontsize=9.5, color=GREY, va="top")
    save(fig, out / "11_solid_angle.svg")


# ------------------------------------------------------------------------------------------
# Irradiance's cosine: one beam over a surface turned further and further from it.

def irradiance_cosine(out):
    fig, axes = plt.subplots(1, 4, figsize=(12, 3.6),
                             gridspec_kw={"width_ratios": [1, 1, 1, 1.25]})
    width = 1.0  # the beam's cross-section
    for ax, tilt in zip(axes[:3], (0, 45, 70)):
        ax.set_xlim(-1.9, 1.9)
        ax.set_ylim(-0.9, 2.4)
        ax.set_aspect("equal")
        ax.axis("off")
        for x in np.linspace(-width / 2 + 0.05, width / 2 - 0.05, 6):
            arrow(ax, (x, 2.2), (x, math.tan(math.radians(tilt)) * x + 0.03), GOLD, 1.0)
        ax.add_patch(Polygon([(-width / 2, 2.2), (width / 2, 2.2),
                              (width / 2, math.tan(math.radians(tilt)) * width / 2),
                              (-width / 2, -math.tan(math.radians(tilt)) * width / 2)],
                             closed=True, facecolor=GOLD, alpha=0.12, edgecolor="none"))
        direction = np.array([math.cos(math.radians(tilt)), math.sin(math.radians(tilt))])
        ax.plot(*zip(-1.6 * direction, 1.6 * direction), color=GREY, linewidth=1.5)
        lit = width / 2 / math.cos(math.radians(tilt))
        ax.plot(*zip(-lit * direction, lit * direction), color=RED, linewidth=4,
                solid_capstyle="butt")
        normal = np.array([-direction[1], direction[0]])
        arrow(ax, (0, 0), tuple(0.9 * normal), BLUE)
        if tilt:
            angle_arc(ax, np.array([0.0, 0.0]), 1.1, normal, np.array([0.0, 1.0]), BLUE)
            ax.text(*(0.7 * unit(normal + np.array([0.0, 1.0])) + [0.02, 0.02]), "θ",
                    fontsize=10, color=BLUE)
        cosine = math.cos(math.radians(tilt))
        ax.text(0, -0.6, f"θ = {tilt}°: lit area A / cos θ = {1 / cosine:.2f} A"
                f"\nE = Φ cos θ / A = {cosine:.2f} E₀", fontsize=8,
                color=RED, ha="center", va="top")
    axes[0].text(0.65, 2.2, "a beam:\nflux Φ,\ncross-\nsection A", fontsize=8.5,
                 color=GOLD, va="top")
    ax = axes[3]
    theta = np.linspace(0, 90, 200)
    ax.plot(theta, np.cos(np.radians(theta)), color=RED, linewidth=2)
    for tilt in (0, 45, 70):
        ax.plot([tilt], [math.cos(math.radians(tilt))], "o", color=RED, markersize=4)
    ax.set_xlim(0, 90)
    ax.set_ylim(0, 1.05)
    ax.set_xticks([0, 30, 45, 60, 70, 90])
    ax.set_xlabel("θ between the normal and the beam (degrees)", fontsize=8.5)
    ax.set_ylabel("irradiance / E₀", fontsize=8.5)
    ax.set_title("E = E₀ cos θ: the same power\non more area", fontsize=9)
    ax.tick_params(labelsize=8)
    fig.subplots_adjust(wspace=0.15)
    save(fig, out / "11_irradiance_cosine.svg")


def main():
    plt.rcParams.update({"svg.hashsalt": "rt-course-ch11", "font.family": "DejaVu Sans"})
    out = Path(sys.argv[1] if len(sys.argv) > 1 else "book/images")
    out.mkdir(parents=True, exist_ok=True)
    area_to_solid_angle(out)
    mis_weights(out)
    kernel_shapes(out)
    solid_angle(out)
    irradiance_cosine(out)


if __name__ == "__main__":
    main()
