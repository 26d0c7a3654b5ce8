#!/usr/bin/env python3
"""Chapter 11b's diagrams (book/images/11b_*): samples that converge faster. Every point drawn
here comes from the course's own samplers, written as CSV by ch11_sample_points, and every
image from the path tracer itself, as radiance (.pfm); the script only counts and draws.

  the points of the independent, stratified and Sobol' samplers, 16 and 256 of them, with the
    grid of strata and the elementary intervals of one split (11b_points.svg);
  the local discrepancy of boxes anchored at the origin, the idea behind Koksma and Hlawka's
    bound (11b_discrepancy.svg);
  Owen's scrambling as a tree of coin flips over the first three digits (11b_owen_tree.svg);
  the Morton order of an 8x8 image, zsobol's order with its quads permuted, and the net its
    pixels' first samples make (11b_morton.svg);
  the four samplers' error against samples and the error's low-pass share, from the report in
    book/data (11b_convergence.svg);
  the room at 4 samples per pixel with each sampler, its error against a reference, and the
    error's power spectrum (11b_room_*.png, 11b_error_*.png, 11b_spectra.svg).

  tools/diagrams/ch11b.py OUT_DIR SCRATCH_DIR [REPORT_JSON]
    SCRATCH_DIR holds what tools/book-images.sh wrote there: 11b_points_<sampler>_<n>.csv,
    11b_zsobol_image.csv, 11b_zsobol_order.csv, 11b_room_<sampler>.pfm and .png,
    11b_room_reference.pfm
    REPORT_JSON defaults to book/data/11b_samplers_cpu_room.json
"""
import csv
import json
import sys
from pathlib import Path

import matplotlib

matplotlib.use("svg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.patches import Circle, FancyArrowPatch, Rectangle  # noqa: E402
from PIL import Image  # noqa: E402

BLUE, GREY, RED, GOLD, GREEN = "#2a7ab0", "#555555", "#c0392b", "#d4a017", "#2e8b57"
PURPLE = "#7b4fa0"
SAMPLERS = ("independent", "stratified", "sobol", "zsobol")
COLOURS = {"independent": GREY, "stratified": GOLD, "sobol": BLUE, "zsobol": RED}
NAMES = {"independent": "independent", "stratified": "stratified",
         "sobol": "Sobol' (padded, Owen-scrambled)", "zsobol": "zsobol (Morton order)"}


def save(fig, path):
    fig.savefig(path, format="svg", metadata={"Date": None}, bbox_inches="tight")
    plt.close(fig)


def read_points(folder, sampler, count):
    with open(folder / f"11b_points_{sampler}_{count}.csv") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == count, f"{sampler}: {len(rows)} points, expected {count}"
    return (np.array([float(r["u"]) for r in rows]), np.array([float(r["v"]) for r in rows]))


def boxes_holding(u, v, columns, rows):
    """How many points fall in each box of a columns x rows grid of [0,1)^2 (rows, columns)."""
    counts = np.zeros((rows, columns), dtype=int)
    np.add.at(counts, ((v * rows).astype(int), (u * columns).astype(int)), 1)
    return counts


def is_net(u, v):
    """True when every elementary interval of area 1/n (n a power of two) holds one point."""
    n = len(u)
    m = n.bit_length() - 1
    return all((boxes_holding(u, v, 2 ** k, 2 ** (m - k)) == 1).all() for k in range(m + 1))


def unit_square(ax):
    ax.set_xlim(0, 1)
    ax.set_ylim(0, 1)
    ax.set_aspect("equal")
    ax.set_xticks([0, 0.5, 1])
    ax.set_yticks([0, 0.5, 1])
    ax.tick_params(labelsize=7, length=2)


def grid_lines(ax, columns, rows, colour, width=0.6):
    for i in range(1, columns):
        ax.axvline(i / columns, color=colour, linewidth=width, zorder=1)
    for j in range(1, rows):
        ax.axhline(j / rows, color=colour, linewidth=width, zorder=1)


# ------------------------------------------------------------------------------------------
# (a) Clumps and gaps, strata, nets.

# The split whose elementary intervals are drawn over the Sobol' points: not the square grid,
# which stratification also fills, but boxes of another shape of the same area.
SOBOL_SPLIT = {16: (8, 2), 256: (32, 8)}


def points(out, folder):
    fig, axes = plt.subplots(2, 3, figsize=(11, 7.6))
    for row, count in enumerate((16, 256)):
        cells = int(round(count ** 0.5))
        size = 16 if count == 16 else 5
        for ax, sampler in zip(axes[row], ("independent", "stratified", "sobol")):
            u, v = read_points(folder, sampler, count)
            unit_square(ax)
            if sampler == "independent":
                counts = boxes_holding(u, v, cells, cells)
                for j, i in zip(*np.nonzero(counts == 0)):
                    ax.add_patch(Rectangle((i / cells, j / cells), 1 / cells, 1 / cells,
                                           facecolor=RED, alpha=0.15, edgecolor="none"))
                grid_lines(ax, cells, cells, "#dddddd")
                title = (f"independent, {count} points:\n{int((counts == 0).sum())} of the "
                         f"{cells}×{cells} cells empty, {int((counts > 1).sum())} "
                         "with more than one")
            elif sampler == "stratified":
                counts = boxes_holding(u, v, cells, cells)
                assert (counts == 1).all(), "stratified: a cell without its one point"
                grid_lines(ax, cells, cells, GOLD)
                title = f"stratified, {count} points:\none in each of the {cells}×{cells} cells"
            else:
                columns, rows = SOBOL_SPLIT[count]
                assert is_net(u, v), f"sobol: {count} points are not a (0,2)-net"
                grid_lines(ax, columns, rows, "#9ec5e0")
                title = (f"Sobol', {count} points: one in each\n1/{columns} × 1/{rows} box "
                         "(and each box of any\nother shape of area 1/" f"{count})")
            ax.scatter(u, v, s=size, color=COLOURS[sampler], zorder=3, linewidths=0)
            ax.set_title(title, fontsize=9)
    fig.subplots_adjust(wspace=0.3, hspace=0.45)
    save(fig, out / "11b_points.svg")


# ------------------------------------------------------------------------------------------
# (b) Local discrepancy: the share of the points in [0,a) x [0,b) against its area a b.

def local_discrepancy(u, v, a, b):
    inside = (u[:, None, None] < a[None, :, None]) & (v[:, None, None] < b[None, None, :])
    return inside.mean(axis=0) - a[:, None] * b[None, :]


def worst_box(u, v):
    """The anchored box whose share of the points is furthest from its area (corners at the
    points' coordinates, where the extremes lie, boxes taken open and closed)."""
    best = (0.0, 1.0, 1.0)
    corners_u, corners_v = np.append(np.sort(u), 1.0), np.append(np.sort(v), 1.0)
    for closed in (False, True):
        lower_u = u[:, None, None] <= corners_u[None, :, None] if closed else \
            u[:, None, None] < corners_u[None, :, None]
        lower_v = v[:, None, None] <= corners_v[None, None, :] if closed else \
            v[:, None, None] < corners_v[None, None, :]
        gap = (lower_u & lower_v).mean(axis=0) - corners_u[:, None] * corners_v[None, :]
        i, j = np.unravel_index(np.abs(gap).argmax(), gap.shape)
        if abs(gap[i, j]) > abs(best[0]):
            best = (gap[i, j], corners_u[i], corners_v[j])
    return best


def discrepancy(out, folder):
    count = 64
    grid = np.linspace(0.0, 1.0, 121)[1:]
    samplers = ("independent", "sobol")
    maps = {s: local_discrepancy(*read_points(folder, s, count), grid, grid) for s in samplers}
    limit = max(np.abs(m).max() for m in maps.values())
    fig, axes = plt.subplots(2, 2, figsize=(9.4, 9.0))
    for row, sampler in enumerate(samplers):
        u, v = read_points(folder, sampler, count)
        gap, a, b = worst_box(u, v)
        ax = axes[row][0]
        unit_square(ax)
        ax.add_patch(Rectangle((0, 0), a, b, facecolor=COLOURS[sampler], alpha=0.12,
                               edgecolor=COLOURS[sampler], linewidth=1.2))
        ax.scatter(u, v, s=12, color=COLOURS[sampler], zorder=3, linewidths=0)
        inside = int(round((gap + a * b) * count))
        ax.set_title(f"{NAMES[sampler]}, {count} points: the worst box\n"
                     f"[0, {a:.2f}) × [0, {b:.2f}): area {a * b:.3f}, holds {inside} points "
                     f"= {inside / count:.3f}", fontsize=9)
        ax = axes[row][1]
        shown = ax.imshow(maps[sampler].T, origin="lower", extent=(0, 1, 0, 1), cmap="RdBu_r",
                          interpolation="none", vmin=-limit, vmax=limit)
        ax.plot([a], [b], "o", markerfacecolor="none", markeredgecolor="black", markersize=7)
        ax.set_xticks([0, 0.5, 1])
        ax.set_yticks([0, 0.5, 1])
        ax.tick_params(labelsize=7, length=2)
        ax.set_xlabel("the box's corner a", fontsize=8)
        ax.set_ylabel("b", fontsize=8)
        ax.set_title(f"share of the points in [0,a)×[0,b) minus its area\nlargest gap "
                     f"(the star discrepancy) {abs(gap):.3f}", fontsize=9)
        print(f"{sampler}: star discrepancy of {count} points {abs(gap):.4f} "
              f"(box {a:.3f} x {b:.3f})")
    fig.subplots_adjust(wspace=0.3, hspace=0.35, right=0.86)
    bar = fig.colorbar(shown, cax=fig.add_axes([0.89, 0.3, 0.018, 0.4]))
    bar.set_label("fraction of the points inside − area", fontsize=8)
    bar.ax.tick_params(labelsize=7)
    save(fig, out / "11b_discrepancy.svg")


# ------------------------------------------------------------------------------------------
# (c) Owen's scrambling: a coin per node of the tree of digits.

# Which coins come up "flip", by the digits above them (illustrative: one draw of the coins).
COINS = {"": 1, "0": 0, "1": 1, "00": 1, "01": 0, "10": 0, "11": 1}


def scrambled(digits):
    """The three digits after Owen's scrambling: digit k flipped by the coin of the digits
    before it, taken as they were before any flip."""
    return "".join(str(int(d) ^ COINS[digits[:k]]) for k, d in enumerate(digits))


def owen_tree(out):
    fig, ax = plt.subplots(figsize=(11, 7.6))
    ax.set_xlim(-0.9, 9.6)
    ax.set_ylim(-2.75, 3.85)
    ax.set_aspect("equal")
    ax.axis("off")
    levels = {0: 3.2, 1: 2.25, 2: 1.3}
    leaf_y = 0.45  # the top of the row of eighths
    centre = {}
    for prefix in COINS:
        span = 8 / 2 ** len(prefix)
        first = int(prefix, 2) * span if prefix else 0
        centre[prefix] = (first + span / 2, levels[len(prefix)])
    for prefix, (x, y) in centre.items():  # the edges first, under the coins
        for digit in "01":
            child = prefix + digit
            end = centre[child] if child in centre else (int(child, 2) + 0.5, leaf_y)
            ax.plot([x, end[0]], [y, end[1]], color="#bbbbbb", linewidth=1, zorder=1)
            ax.text(x + 0.4 * (end[0] - x) + (-0.12 if digit == "0" else 0.12),
                    y + 0.4 * (end[1] - y), digit, fontsize=8, color=GREY, ha="center",
                    va="center")
    for prefix, (x, y) in centre.items():
        flip = COINS[prefix] == 1
        ax.add_patch(Circle((x, y), 0.27, facecolor=RED if flip else "white",
                            edgecolor=RED, linewidth=1.3, zorder=2))
        ax.text(x, y, "flip" if flip else "keep", fontsize=7.5, ha="center", va="center",
                color="white" if flip else RED, zorder=3)
        ax.text(x, y + 0.32, f"after {prefix}" if prefix else "every point", fontsize=7,
                color=GREY, ha="center", va="bottom")
    for depth, y in levels.items():
        ax.text(-0.85, y, f"coin{'s' if depth else ''} for\ndigit {depth + 1}", fontsize=8,
                color=GREY, va="center")
    # The eight intervals before and after, and where each one goes: the interval at place
    # k after the flips is labelled with the digits it had before them.
    before_y, after_y = 0.0, -1.75
    for k in range(8):
        digits = format(k, "03b")
        target = int(scrambled(digits), 2)
        ax.add_patch(Rectangle((k, before_y), 1, 0.45, facecolor="white", edgecolor=GREY,
                               linewidth=0.8))
        ax.text(k + 0.5, before_y + 0.22, digits, fontsize=8, ha="center", va="center",
                color=BLUE)
        ax.add_patch(Rectangle((target, after_y), 1, 0.45, facecolor="#f3eef8",
                               edgecolor=GREY, linewidth=0.8))
        ax.text(target + 0.5, after_y + 0.22, digits, fontsize=8, ha="center", va="center",
                color=PURPLE)
        ax.add_patch(FancyArrowPatch((k + 0.5, before_y - 0.05), (target + 0.5, after_y + 0.5),
                                     arrowstyle="-|>", mutation_scale=9, color=PURPLE,
                                     linewidth=0.8))
    ax.text(8.15, before_y + 0.22, "[0, 1) in eighths,\nby a point's first\nthree digits",
            fontsize=8, color=BLUE, va="center")
    ax.text(8.15, after_y + 0.22, "where each eighth\nlands: the halves,\nquarters, eighths\n"
            "move whole", fontsize=8, color=PURPLE, va="center")
    ax.text(-0.85, -2.0, "Each digit is flipped by the coin its digits above choose (read "
            "before any flip). Points that share their first k digits share them after: a box "
            "of a net goes\nwhole to a box of the same size, so a net stays a net. On the "
            "bit-reversed number the digits above a digit are the bits below it, all that "
            "x ^= x · (even) can reach.", fontsize=7.5, color=GREY, va="top")
    save(fig, out / "11b_owen_tree.svg")


# ------------------------------------------------------------------------------------------
# (d) Morton order, its quads permuted, and the net that the image's first samples make.

def read_rows(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def pixel_grid(ax, side, labels, colours, order, title, line_colour):
    ax.set_xlim(0, side)
    ax.set_ylim(side, 0)  # row 0 at the top, as in the image
    ax.set_aspect("equal")
    ax.set_xticks([])
    ax.set_yticks([])
    for (x, y), colour, label in zip(order["xy"], colours, labels):
        ax.add_patch(Rectangle((x, y), 1, 1, facecolor=colour, edgecolor="white",
                               linewidth=0.6))
        ax.text(x + 0.3, y + 0.32, str(label), fontsize=6.5, ha="center", va="center",
                color="black")
    for step, width in ((2, 0.8), (4, 1.6)):  # the quads, and the quads of quads
        for k in range(0, side + 1, step):
            ax.plot([k, k], [0, side], color=GREY, linewidth=width)
            ax.plot([0, side], [k, k], color=GREY, linewidth=width)
    path = sorted(zip(order["rank"], order["xy"]))
    ax.plot([x + 0.5 for _, (x, _y) in path], [y + 0.5 for _, (_x, y) in path],
            color=line_colour, linewidth=1.0, alpha=0.8)
    ax.set_title(title, fontsize=9)


def morton(out, folder):
    order = read_rows(folder / "11b_zsobol_order.csv")
    image = read_rows(folder / "11b_zsobol_image.csv")
    side = max(int(r["x"]) for r in order) + 1
    assert len(order) == side * side and len(image) == side * side
    xy = [(int(r["x"]), int(r["y"])) for r in order]
    morton_codes = [int(r["morton"]) for r in order]
    index = [int(r["index"]) for r in order]
    assert sorted(index) == list(range(side * side)), "zsobol: not one index per pixel"
    cmap = plt.get_cmap("viridis")
    fig, axes = plt.subplots(2, 2, figsize=(10, 10.4))
    pixel_grid(axes[0][0], side, morton_codes, ["#eef3f8"] * len(xy),
               {"xy": xy, "rank": morton_codes},
               "Morton order: the bits of x and y interleaved.\nEvery 2×2 quad, and every quad "
               "of quads, is a run", BLUE)
    colours = [cmap(0.25 + 0.75 * i / (side * side - 1)) for i in index]
    colours = [(r, g, b, 0.55) for r, g, b, _ in colours]
    pixel_grid(axes[0][1], side, index, colours, {"xy": xy, "rank": index},
               "zsobol's order: each base-4 digit permuted\n(a quad's four children shuffled, "
               "by a hash of the digits above)", RED)
    # The first sample of every pixel, in [0,1)^2, coloured by its pixel's index.
    u = np.array([float(r["u"]) for r in image])
    v = np.array([float(r["v"]) for r in image])
    assert is_net(u, v), "zsobol: the image's first samples are not a (0,2)-net"
    quarter_colours = (BLUE, GOLD, GREEN, PURPLE)  # [0,1/2)^2, then right, top, top right
    ax = axes[1][0]
    unit_square(ax)
    for k, colour in enumerate(quarter_colours):
        ax.add_patch(Rectangle((0.5 * (k % 2), 0.5 * (k // 2)), 0.5, 0.5, facecolor=colour,
                               alpha=0.12, edgecolor="none"))
    grid_lines(ax, side, side, "#dddddd")
    point_index = {int(r["pixel"]): int(r["index"]) for r in order}
    ranks = np.array([point_index[int(r["pixel"])] for r in image])
    ax.scatter(u, v, s=22, c=[cmap(0.25 + 0.75 * i / (side * side - 1)) for i in ranks],
               zorder=3, linewidths=0)
    ax.set_title(f"sample 0 of all {side * side} pixels, coloured by index:\none point in "
                 f"each 1/{side} × 1/{side} box: the whole image one net\n(its quarters "
                 "tinted as in the next panel)", fontsize=9)
    # Which quarter of the square each pixel's point fell in: every quad holds all four.
    ax = axes[1][1]
    quarter = (u >= 0.5).astype(int) + 2 * (v >= 0.5).astype(int)
    by_pixel = {int(r["pixel"]): q for r, q in zip(image, quarter)}
    colours = [quarter_colours[by_pixel[int(r["pixel"])]] for r in order]
    for (x, y), colour in zip(xy, colours):
        ax.add_patch(Rectangle((x, y), 1, 1, facecolor=colour, alpha=0.7, edgecolor="white",
                               linewidth=0.6))
    for k in range(0, side + 1, 2):
        ax.plot([k, k], [0, side], color=GREY, linewidth=1.2)
        ax.plot([0, side], [k, k], color=GREY, linewidth=1.2)
    ax.set_xlim(0, side)
    ax.set_ylim(side, 0)
    ax.set_aspect("equal")
    ax.set_xticks([])
    ax.set_yticks([])
    quads_complete = all(
        sorted(by_pixel[(y + dy) * side + x + dx] for dx in (0, 1) for dy in (0, 1)) ==
        [0, 1, 2, 3] for x in range(0, side, 2) for y in range(0, side, 2))
    assert quads_complete, "zsobol: a quad without a point in each quarter"
    ax.set_title("the quarter of [0,1)² each pixel's point fell in:\nevery 2×2 quad holds "
                 "all four, so their errors offset", fontsize=9)
    fig.subplots_adjust(wspace=0.12, hspace=0.22)
    save(fig, out / "11b_morton.svg")


# ------------------------------------------------------------------------------------------
# (e) Error against samples, from the report.

def sampler_of(variant):
    words = variant.split(", ")
    for word in words:
        if word.endswith(" sampler"):
            return word[: -len(" sampler")]
    return "independent"


def fitted_slope(samples, error):
    """Least squares in log-log, as convergence_slope does for the report's MSE."""
    return float(np.polyfit(np.log(samples), np.log(error), 1)[0])


def convergence(out, report_path):
    report = json.loads(Path(report_path).read_text())
    series = {s: [] for s in SAMPLERS}
    for row in report["rows"]:
        m = row["metrics"]
        series[sampler_of(row["variant"])].append(
            (m["samples"], m["rmse"] ** 2, m["rel_mse"], m["error_lowpass"], m["wall_ms"]))
    fig, (left, middle, right) = plt.subplots(1, 3, figsize=(15, 4.6))
    for sampler in SAMPLERS:
        samples, mse, rel_mse, lowpass, wall_ms = (np.array(c)
                                                   for c in zip(*sorted(series[sampler])))
        colour = COLOURS[sampler]
        left.loglog(samples, mse, "o-", color=colour, markersize=3.5,
                    label=f"{NAMES[sampler]}: slope {fitted_slope(samples, mse):.2f}")
        middle.loglog(samples, rel_mse, "o-", color=colour, markersize=3.5,
                      label=f"{NAMES[sampler]}: slope {fitted_slope(samples, rel_mse):.2f}")
        right.semilogx(samples, lowpass, "o-", color=colour, markersize=3.5,
                       label=NAMES[sampler])
        print(f"{sampler}: MSE slope {fitted_slope(samples, mse):.3f}, relMSE slope "
              f"{fitted_slope(samples, rel_mse):.3f}; at {samples[-1]:.0f} spp MSE {mse[-1]:.3g}, "
              f"relMSE {rel_mse[-1]:.3g}, {wall_ms[-1]:.0f} ms; low-pass share at 4 spp "
              f"{lowpass[samples == 4][0]:.3f}")
    independent = sorted(series["independent"])
    guide = np.array([1.0, independent[-1][0]])
    for ax, column in ((left, 1), (middle, 2)):
        ax.loglog(guide, independent[0][column] / guide, ":", color="#999999", linewidth=1,
                  label="slope −1 (independent samples)")
        ax.legend(fontsize=7.5, frameon=False)
    for ax in (left, middle, right):
        ax.set_xscale("log", base=2)
        ax.set_xlabel("samples per pixel", fontsize=9)
        ax.tick_params(labelsize=8)
        ax.grid(True, which="major", color="#eeeeee")
    left.set_ylabel("MSE (RMSE²) against the reference", fontsize=9)
    left.set_title("MSE: bright pixels weigh most", fontsize=10)
    middle.set_ylabel("relative MSE", fontsize=9)
    middle.set_title("relative MSE: every pixel alike", fontsize=10)
    right.axhline(1 / 9, color="#999999", linestyle=":", linewidth=1)
    right.text(1.1, 1 / 9 + 0.003, "white noise: 1/9", fontsize=8, color=GREY)
    right.set_ylabel("share of the error a 3×3 box filter keeps", fontsize=9)
    right.set_title("the error's low-pass share (lower: bluer)", fontsize=10)
    right.legend(fontsize=7.5, frameon=False)
    context = report["context"]
    fig.suptitle(f"Chapter 11b: the samplers in the Cornell room on the CPU "
                 f"({context.get('resolution', '?')}, reference: {report['reference']}; each "
                 "point a fresh image)", fontsize=10)
    fig.subplots_adjust(wspace=0.28, top=0.86)
    save(fig, out / "11b_convergence.svg")


def gpu_convergence(out, data=Path("book/data")):
    """The three scenes on an H200 (tools/gpu/run.sh's samplers step): each sampler's MSE
    against the independent sampler's at the same count, so that the gain reads directly."""
    scenes = [("room", "Cornell room"), ("sponza-dabrovic", "Sponza, sun and sky"),
              ("conference", "conference room, sun and sky")]
    paths = [data / f"11b_samplers_h200_{name}.json" for name, _ in scenes]
    if not all(p.exists() for p in paths):
        return
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.2), sharey=True)
    for ax, (name, title), path in zip(axes, scenes, paths):
        report = json.loads(path.read_text())
        series = {s: {} for s in SAMPLERS}
        for row in report["rows"]:
            m = row["metrics"]
            series[sampler_of(row["variant"])][m["samples"]] = m["rmse"] ** 2
        counts = sorted(series["independent"])
        for sampler in SAMPLERS:
            ratio = [series[sampler][n] / series["independent"][n] for n in counts]
            ax.semilogx(counts, ratio, "o-", color=COLOURS[sampler], markersize=3.5,
                        label=NAMES[sampler])
        ax.set_xscale("log", base=2)
        ax.set_title(f"{title} ({report['context'].get('resolution', '?')})", fontsize=10)
        ax.set_xlabel("samples per pixel", fontsize=9)
        ax.axhline(0.55, color="#999999", linestyle=":", linewidth=1)
        ax.tick_params(labelsize=8)
        ax.grid(True, which="major", color="#eeeeee")
    axes[0].text(1.1, 0.57, "0.55", fontsize=8, color=GREY)
    axes[0].set_ylabel("MSE against the independent sampler's", fontsize=9)
    axes[0].legend(fontsize=8, frameon=False)
    fig.suptitle("Chapter 11b on an NVIDIA H200: each sampler's MSE over the independent "
                 "sampler's at the same samples per pixel (reference: 16 384 samples)",
                 fontsize=10)
    fig.subplots_adjust(wspace=0.08, top=0.85)
    save(fig, out / "11b_convergence_h200.svg")


# ------------------------------------------------------------------------------------------
# (f) The room at 4 samples per pixel: its error, and the error's spectrum.

def read_pfm(path):
    with open(path, "rb") as f:
        assert f.readline().strip() == b"PF", f"{path}: not a colour PFM file"
        width, height = (int(x) for x in f.readline().split())
        scale = float(f.readline())
        data = np.frombuffer(f.read(), dtype="<f4" if scale < 0 else ">f4")
    return data.reshape(height, width, 3)[::-1].astype(np.float64)  # bottom row first


def luminance(rgb):
    return rgb @ np.array([0.2126, 0.7152, 0.0722])  # path_sampling.h's weights


def save_png(array, path):
    Image.fromarray(array).save(path, optimize=True)


def radial_spectrum(error, rings=20):
    """The error's power spectrum, averaged over rings of equal frequency (cycles per pixel):
    flat for white noise, low at low frequencies for blue noise."""
    h, w = error.shape
    power = np.abs(np.fft.fft2(error - error.mean())) ** 2 / (h * w)
    fy, fx = np.meshgrid(np.fft.fftfreq(h), np.fft.fftfreq(w), indexing="ij")
    radius = np.hypot(fx, fy)
    edges = np.linspace(0.0, 0.5, rings + 1)
    ring = np.digitize(radius, edges) - 1
    keep = (ring >= 0) & (ring < rings) & (radius > 0)
    sums = np.bincount(ring[keep], weights=power[keep], minlength=rings)
    counts = np.bincount(ring[keep], minlength=rings)
    return (edges[:-1] + edges[1:]) / 2, sums / np.maximum(counts, 1)


def box_share(error):
    """What a 3 x 3 box filter keeps of the error's mean square, as lowpass_share measures it
    (convergence.h), here of one luminance image."""
    h, w = error.shape
    box = sum(error[1 + dy:h - 1 + dy, 1 + dx:w - 1 + dx] for dy in (-1, 0, 1)
              for dx in (-1, 0, 1)) / 9
    return float((box ** 2).mean() / (error[1:-1, 1:-1] ** 2).mean())


# The share of the error's largest values clamped before the spectrum: a few pixels (the
# lamp's edge, rare bright paths) hold most of the squared error, and one of them alone is a
# flat spectrum that hides how the others lie against their neighbours.
CLAMP_PERCENTILE = 99


def room(out, folder):
    for sampler in SAMPLERS:  # the program's own pictures, kept as RGB and compressed harder
        Image.open(folder / f"11b_room_{sampler}.png").convert("RGB").save(
            out / f"11b_room_{sampler}.png", optimize=True)
    reference = read_pfm(folder / "11b_room_reference.pfm")
    errors = {s: luminance(read_pfm(folder / f"11b_room_{s}.pfm") - reference)
              for s in SAMPLERS}
    # Grey is no error; black and white are -+4 times the independent sampler's median error.
    scale = 4.0 * np.median(np.abs(errors["independent"]))
    for sampler, error in errors.items():
        grey = np.clip(0.5 + 0.5 * error / scale, 0.0, 1.0)
        save_png((grey * 255 + 0.5).astype(np.uint8), out / f"11b_error_{sampler}.png")
    fig, (left, right) = plt.subplots(1, 2, figsize=(11.5, 4.4))
    for sampler, error in errors.items():
        limit = np.percentile(np.abs(error), CLAMP_PERCENTILE)
        frequency, power = radial_spectrum(np.clip(error, -limit, limit))
        high = power[frequency >= 0.25].mean()
        left.semilogy(frequency, power, "o-", color=COLOURS[sampler], linewidth=1.4,
                      markersize=3, label=NAMES[sampler])
        right.plot(frequency, power / high, "o-", color=COLOURS[sampler], linewidth=1.4,
                   markersize=3, label=NAMES[sampler])
        top = np.sort(error.ravel() ** 2)[::-1]
        print(f"{sampler}: luminance MSE at 4 spp {(error ** 2).mean():.4g}, 3x3 box share "
              f"{box_share(error):.3f} (clamped {box_share(np.clip(error, -limit, limit)):.3f}),"
              f" the top 1% of pixels hold {top[:len(top) // 100].sum() / top.sum():.2f} of "
              f"the squared error; clamped power below 0.1 cycles / above 0.25: "
              f"{power[frequency < 0.1].mean() / high:.3f}")
    for ax in (left, right):
        ax.set_xlabel("frequency (cycles per pixel; 0.5: from one pixel to the next)",
                      fontsize=9)
        ax.tick_params(labelsize=8)
        ax.grid(True, color="#eeeeee")
        ax.set_xlim(0, 0.5)
        ax.legend(fontsize=8, frameon=False)
    left.set_ylabel("power of the error (luminance)", fontsize=9)
    left.set_title("the error's power spectrum, averaged over rings", fontsize=10)
    right.axhline(1.0, color="#999999", linestyle=":", linewidth=1)
    right.set_ylabel("power over its mean above 0.25 cycles", fontsize=9)
    right.set_title("the same, scaled: white noise is flat at 1", fontsize=10)
    fig.suptitle(f"The Cornell room at 256×256, 4 samples per pixel: the error against the "
                 f"reference (its largest {100 - CLAMP_PERCENTILE}% clamped)", fontsize=10)
    fig.subplots_adjust(wspace=0.25, top=0.86)
    save(fig, out / "11b_spectra.svg")


def main():
    plt.rcParams.update({"svg.hashsalt": "rt-course-ch11b", "font.family": "DejaVu Sans"})
    if len(sys.argv) < 3:
        sys.exit("usage: ch11b.py OUT_DIR SCRATCH_DIR [REPORT_JSON]")
    out, folder = Path(sys.argv[1]), Path(sys.argv[2])
    report = sys.argv[3] if len(sys.argv) > 3 else "book/data/11b_samplers_cpu_room.json"
    out.mkdir(parents=True, exist_ok=True)
    points(out, folder)
    discrepancy(out, folder)
    owen_tree(out)
    morton(out, folder)
    convergence(out, report)
    gpu_convergence(out)
    room(out, folder)


if __name__ == "__main__":
    main()
