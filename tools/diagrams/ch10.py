#!/usr/bin/env python3
"""Chapter 10's diagrams and plots (book/images/10_*): the Morton curve over the torus knot's
triangles, the sorted codes' highest differing bits that split Karras's nodes, Karras's tree over
eight sorted Morton codes, each interior node made by its own thread, PLOC's rounds re-enacted on
a dozen points in the plane, H-PLOC's walk up the LBVH of sixteen points, a treelet of seven
boxes before and after its restructuring, the shares that the parallel collapse's sah rule hands
down a binary subtree to find one wide node's children, and the moving scene's frames, rebuilt
against refitted, from the CSVs the program wrote into book/data: the 2-core machine's (SVG) and
the H200's, torus and dragon, each frame's tree, collapse and trace stacked (PNG).

  tools/diagrams/ch10.py [OUT_DIR]     (default: book/images)
"""
import csv
import gzip
import math
import sys
from pathlib import Path

import matplotlib

matplotlib.use("svg")
matplotlib.rcParams["svg.hashsalt"] = "rt-course-ch10"  # the same file on every run
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import LineCollection  # noqa: E402
from matplotlib.patches import FancyBboxPatch, Rectangle  # noqa: E402

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


MODEL = ROOT / "assets" / "torus_knot_100k.obj.gz"
MODEL_STRIDE = 50  # every 50th triangle of the knot: 2 000 centroids, a curve to follow


def grid_cell(c, lo, hi, bits):
    """morton.h's grid_cell, in float32 as the backends compute it."""
    f = np.float32
    half_extent = f(0.5) * f(hi) - f(0.5) * f(lo)
    if not half_extent > 0:
        return 0
    cells = f(1 << bits)
    q = (f(0.5) * f(c) - f(0.5) * f(lo)) / half_extent * cells
    if not q > 0:
        return 0
    return (1 << bits) - 1 if q >= cells - f(1) else int(q)


def spread(x, axes):
    """Bit k of x moves to bit axes * k: the interleaving of morton.h, one bit at a time."""
    return sum(((x >> k) & 1) << (axes * k) for k in range(10))


def morton_order(points, axes):
    """The points' 10-bit-per-axis codes over their bounds, and the stable sort by code that
    build_passes.cuh's sort_by_code makes (equal codes keep their input order)."""
    lo = [min(p[a] for p in points) for a in range(axes)]
    hi = [max(p[a] for p in points) for a in range(axes)]
    codes = []
    for p in points:
        cells = [grid_cell(p[a], lo[a], hi[a], 10) for a in range(axes)]
        codes.append(sum(spread(cells[a], axes) << (axes - 1 - a) for a in range(axes)))
    order = sorted(range(len(points)), key=lambda k: codes[k])
    return order, codes


def knot_centroids():
    """Centroids of the torus knot's triangles (every MODEL_STRIDE-th), as box centroids."""
    vertices, centroids = [], []
    with gzip.open(MODEL, "rt") as f:
        faces = 0
        for line in f:
            if line.startswith("v "):
                vertices.append([np.float32(v) for v in line.split()[1:4]])
            elif line.startswith("f "):
                if faces % MODEL_STRIDE == 0:
                    corners = [vertices[int(w.split("/")[0]) - 1] for w in line.split()[1:4]]
                    lo = [min(c[a] for c in corners) for a in range(3)]
                    hi = [max(c[a] for c in corners) for a in range(3)]
                    centroids.append([np.float32(0.5) * lo[a] + np.float32(0.5) * hi[a]
                                      for a in range(3)])
                faces += 1
    return centroids


def morton_curve(out):
    """The knot's centroids joined in 30-bit Morton order, seen from above (x, y), coloured by
    place in the sorted array; beside it the same points coloured by their code's top three
    bits (the octant) and top six (the octant's octant): runs of the array that are boxes."""
    points = knot_centroids()
    order, codes = morton_order(points, 3)
    xs = [float(points[k][0]) for k in order]
    ys = [float(points[k][1]) for k in order]
    fig, axes = plt.subplots(1, 3, figsize=(14, 4.9))
    n = len(order)
    colours = plt.get_cmap("viridis")
    segments = [[(xs[a], ys[a]), (xs[a + 1], ys[a + 1])] for a in range(n - 1)]
    axes[0].add_collection(LineCollection(segments, colors=[colours(a / n) for a in range(n - 1)],
                                          linewidth=0.7))
    axes[0].autoscale_view()
    axes[0].set_title(f"{n} centroids joined in Morton order\n(colour: place in the sorted "
                      "array)", fontsize=10)
    for ax, top_bits, name in ((axes[1], 3, "octant"), (axes[2], 6, "octant of an octant")):
        groups = [codes[k] >> (30 - top_bits) for k in order]
        palette = plt.get_cmap("tab10" if top_bits == 3 else "tab20")
        distinct = sorted(set(groups))
        ax.scatter(xs, ys, s=5, c=[palette(distinct.index(g) % palette.N) for g in groups])
        ax.set_title(f"The top {top_bits} bits of the code: the {name}\n({len(distinct)} "
                     "runs of the sorted array, each a box of the grid)", fontsize=10)
    for ax in axes:
        ax.set_aspect("equal")
        ax.set_xticks([])
        ax.set_yticks([])
    neighbour = [math.dist(points[order[a]], points[order[a + 1]]) for a in range(n - 1)]
    neighbour.sort()
    extent = math.dist([min(p[a] for p in points) for a in range(3)],
                       [max(p[a] for p in points) for a in range(3)])
    fig.text(0.5, 0.02, f"Torus knot, every {MODEL_STRIDE}th of its 100 000 triangles. Of "
             f"two centroids next to each other in the array, half lie within "
             f"{neighbour[len(neighbour) // 2] / extent:.3f} of the scene's diagonal, 90 % "
             f"within {neighbour[int(0.9 * len(neighbour))] / extent:.3f}; the longest jump "
             f"is {neighbour[-1] / extent:.2f}.\nSeen from above: an octant also splits the "
             "height, so two colours overlap where the knot passes over itself.",
             ha="center", fontsize=9, color=GREY)
    fig.savefig(out / "10_morton_curve.png", format="png", dpi=90, metadata={"Software": None},
                bbox_inches="tight")
    plt.close(fig)


def karras_split(out):
    """The sorted codes as a grid of bits. Each interior node covers a run of leaves; within
    it the highest bit in which its first and last codes differ is 0 above the split and 1
    below it: the node's column (outlined) and its split (the line across it)."""
    n = len(CODES)
    nodes = {i: karras_node(i) for i in range(n - 1)}
    fig, ax = plt.subplots(figsize=(9.5, 5.2))
    ax.set_xlim(-2.6, BITS + 4.6)
    ax.set_ylim(n + 0.9, -1.3)
    ax.axis("off")
    for bit in range(BITS):
        ax.text(bit + 0.5, -0.35, f"bit {BITS - 1 - bit}", ha="center", fontsize=8,
                color=GREY)
    for k, code in enumerate(CODES):
        ax.text(-0.25, k + 0.5, f"leaf {k}", ha="right", va="center", fontsize=9, color=GREY)
        for bit, digit in enumerate(f"{code:05b}"):
            ax.add_patch(Rectangle((bit, k), 1, 1, facecolor="#eef5fb" if digit == "0"
                                   else "#cfe3f3", edgecolor="white"))
            ax.text(bit + 0.5, k + 0.5, digit, ha="center", va="center", fontsize=11,
                    family="monospace")
    palette = (RED, GREEN, BLUE, "#8e44ad", "#d35400", "#16a085", "#7f8c8d")
    for i, (first, last, split) in sorted(nodes.items()):
        bit = BITS - 1 - delta(first, last)  # the highest bit in which the ends differ
        colour = palette[i % len(palette)]
        column = BITS - 1 - bit
        ax.add_patch(Rectangle((column + 0.06, first + 0.06), 0.88, last - first + 0.88,
                               fill=False, edgecolor=colour, linewidth=2))
        ax.plot([column + 0.06, column + 0.94], [split + 1, split + 1], color=colour,
                linewidth=3)
        x = BITS + 0.4 + 0.85 * column
        ax.plot([x, x], [first + 0.15, last + 0.85], color=colour, linewidth=2)
        ax.plot([x - 0.1, x + 0.1], [split + 1, split + 1], color=colour, linewidth=2)
        ax.text(x + 0.1, (first + last + 1) / 2, f"node {i}", fontsize=8, color=colour,
                va="center", rotation=90)
    ax.text(-2.5, n + 0.55, "Each outline is one interior node: its leaves (rows), the highest "
            "bit in which its first and last codes differ (column),\nand its split, where that "
            "bit turns from 0 to 1 (thick line). Deeper nodes decide by lower bits. The "
            "brackets on the right are the ranges.", fontsize=8.5, color=GREY, va="top")
    save(fig, out / "10_karras_split.svg")
    plt.close(fig)


# A dozen points for PLOC's rounds, the corners of the clusters' boxes being the points
# themselves (boxes of zero size, as far-apart triangles nearly are).
PLOC_POINTS = [(0.9, 1.2), (1.4, 0.7), (2.6, 1.0), (3.1, 1.6), (5.2, 0.8), (5.6, 1.5),
               (1.0, 3.2), (1.9, 3.6), (3.4, 3.0), (4.6, 3.9), (5.4, 3.3), (6.2, 2.6)]
PLOC_RADIUS = 2  # the chapter's builds look 8 places each way; a dozen clusters need fewer


def half_perimeter(box):
    (x0, y0), (x1, y1) = box
    return (x1 - x0) + (y1 - y0)


def join(a, b):
    return ((min(a[0][0], b[0][0]), min(a[0][1], b[0][1])),
            (max(a[1][0], b[1][0]), max(a[1][1], b[1][1])))


def ploc_rounds(points, radius):
    """ploc.cu's rounds in the plane (the box's half perimeter plays the half area): each
    cluster's nearest neighbour within `radius` places, the leftmost of equal ones; mutual
    pairs merge, the left one making the node in its own place. Returns, for every round, the
    clusters (name, box) in array order and their neighbours."""
    order, _ = morton_order(points, 2)
    clusters = [(str(k), (points[k], points[k])) for k in order]
    rounds = []
    while len(clusters) > 1:
        neighbour = []
        for i, (_, own) in enumerate(clusters):
            best, best_area = -1, 0.0
            for j in range(max(0, i - radius), min(len(clusters) - 1, i + radius) + 1):
                if j == i:
                    continue
                area = half_perimeter(join(own, clusters[j][1]))
                if best < 0 or area < best_area:
                    best, best_area = j, area
            neighbour.append(best)
        rounds.append((clusters, neighbour))
        merged = []
        for i, (name, box) in enumerate(clusters):
            j = neighbour[i]
            mutual = neighbour[j] == i
            if mutual and i < j:
                merged.append((f"({name} {clusters[j][0]})", join(box, clusters[j][1])))
            elif not mutual:
                merged.append((name, box))
        clusters = merged
    rounds.append((clusters, [-1]))
    return rounds


def ploc_merges(out):
    rounds = ploc_rounds(PLOC_POINTS, PLOC_RADIUS)
    fig, grid = plt.subplots(2, 3, figsize=(13.5, 8.2))
    for r, (ax, (clusters, neighbour)) in enumerate(zip(grid.flat, rounds)):
        ax.set_xlim(0.3, 6.8)
        ax.set_ylim(-0.9, 4.5)
        ax.set_aspect("equal")
        ax.set_xticks([])
        ax.set_yticks([])
        for k, (x, y) in enumerate(PLOC_POINTS):
            ax.plot(x, y, "o", color=GREY, markersize=3)
            ax.text(x + 0.07, y + 0.07, str(k), fontsize=7, color=GREY)
        pairs = 0
        for i, (name, box) in enumerate(clusters):
            (x0, y0), (x1, y1) = box
            if x1 > x0 or y1 > y0:
                ax.add_patch(Rectangle((x0 - 0.08, y0 - 0.08), x1 - x0 + 0.16,
                                       y1 - y0 + 0.16, fill=False, edgecolor=BLUE))
            j = neighbour[i]
            if j < 0:
                continue
            mutual = neighbour[j] == i
            centre = ((x0 + x1) / 2, (y0 + y1) / 2)
            (u0, v0), (u1, v1) = clusters[j][1]
            target = ((u0 + u1) / 2, (v0 + v1) / 2)
            if mutual and i < j:
                pairs += 1
                (a0, b0), (a1, b1) = join(box, clusters[j][1])
                ax.add_patch(Rectangle((a0 - 0.14, b0 - 0.14), a1 - a0 + 0.28,
                                       b1 - b0 + 0.28, fill=False, edgecolor=RED,
                                       linestyle="--", linewidth=1.5))
            if not (mutual and i > j):
                ax.annotate("", xy=target, xytext=centre,
                            arrowprops=dict(arrowstyle="<->" if mutual else "->",
                                            color=RED if mutual else GREY, linewidth=1.2,
                                            shrinkA=2, shrinkB=2))
        names = " ".join(name for name, _ in clusters)
        if len(clusters) > 1:
            ax.set_title(f"Round {r + 1}: {len(clusters)} clusters, {pairs} mutual pairs",
                         fontsize=10)
        else:
            ax.set_title("The root", fontsize=10)
        if len(names) > 42:  # the array in two lines, broken between two clusters
            depth, gaps = 0, []  # (nesting depth, place) of every space
            for at, letter in enumerate(names):
                depth += {"(": 1, ")": -1}.get(letter, 0)
                if letter == " ":
                    gaps.append((depth, abs(at - len(names) // 2), at))
            cut = min(gaps)[2]
            names = names[:cut] + "\n" + names[cut + 1:]
        ax.text(3.55, -0.2, names, ha="center", va="top", fontsize=8, family="monospace")
    fig.text(0.5, 0.02, f"Below each panel the array of clusters in Morton order. Grey arrow: a "
             f"cluster's nearest neighbour within {PLOC_RADIUS} places of it (the smallest "
             "merged box). Red: two clusters\nthat chose each other; dashed: the box of the "
             "node they make at the end of the round, in the left one's place. Blue: "
             "clusters made in earlier rounds.", ha="center", fontsize=9.5, color=GREY)
    save(fig, out / "10_ploc_rounds.svg")
    plt.close(fig)


# Sixteen points for H-PLOC's walk up the LBVH. The chapter's builds pass up at most 16
# clusters per subtree and look 8 places each way; sixteen points need a list of 3 and a
# window of 2 to show a few merges.
HPLOC_POINTS = [(0.6, 0.8), (1.5, 1.3), (0.9, 2.0), (2.1, 0.5), (3.2, 1.1), (3.9, 0.4),
                (3.5, 2.2), (4.6, 1.6), (0.7, 3.4), (1.8, 2.9), (2.4, 3.8), (1.2, 4.4),
                (5.3, 0.9), (6.4, 1.4), (5.8, 3.1), (6.9, 3.9)]
HPLOC_THRESHOLD, HPLOC_RADIUS = 3, 2
NODE_NAMES = "ABCDEFGHJKLMNPQRSTUVWXYZ"  # no I or O, which read as 1 and 0


def radix_tree(keys, first, last):
    """Karras's hierarchy over sorted unique keys, top down: the split is where the highest bit
    in which the range's first and last keys differ turns from 0 to 1. Returns a leaf number
    or (first, last, left, right)."""
    if first == last:
        return first
    bit = (keys[first] ^ keys[last]).bit_length() - 1
    split = next(k for k in range(first, last + 1) if keys[k] >> bit & 1)
    return (first, last, radix_tree(keys, first, split - 1), radix_tree(keys, split, last))


def hploc_list_merge(clusters, target, radius, names):
    """hploc.h's merge_cluster_list on (name, box) clusters, the half perimeter for the half
    area: mutual nearest neighbours within `radius` merge, the left one's place kept, until
    `target` are left. New nodes are named A, B, ... in the order made (their boxes kept in
    `names`)."""
    while len(clusters) > target:
        neighbour = []
        for i, (_, own) in enumerate(clusters):
            best, best_cost = -1, 0.0
            for j in range(max(0, i - radius), min(len(clusters) - 1, i + radius) + 1):
                if j != i:
                    cost = half_perimeter(join(own, clusters[j][1]))
                    if best < 0 or cost < best_cost:
                        best, best_cost = j, cost
            neighbour.append(best)
        merged = []
        for i, (name, box) in enumerate(clusters):
            j = neighbour[i]
            mutual = neighbour[j] == i
            if mutual and i < j:
                node = NODE_NAMES[len(names)]
                names[node] = join(box, clusters[j][1])
                merged.append((node, names[node]))
            elif not mutual:
                merged.append((name, box))
        clusters = merged
    return clusters


def hploc_walk(out):
    """The LBVH over sixteen points, each subtree labelled with the clusters it passes up;
    red where the list grew past the threshold (or reached the root) and PLOC ran inside it.
    Beside it the points and the boxes of the nodes the merges made."""
    order, codes = morton_order(HPLOC_POINTS, 2)
    points = [HPLOC_POINTS[k] for k in order]  # leaf k is the k-th point in Morton order
    keys = [codes[order[k]] << 4 | k for k in range(len(points))]  # the index breaks ties
    tree = radix_tree(keys, 0, len(points) - 1)
    names = {}  # node letter -> box
    labels = []  # (first, last, depth, list, merged)
    root_first = []  # the number of the first node the root's merges made

    def walk(node, depth):
        if isinstance(node, int):
            return [(str(node), (points[node], points[node]))], 0
        first, last, left, right = node
        left_list, left_depth = walk(left, depth + 1)
        right_list, right_depth = walk(right, depth + 1)
        clusters = left_list + right_list
        root = first == 0 and last == len(points) - 1
        merged = last - first + 1 > HPLOC_THRESHOLD or root
        if merged:
            if root:
                root_first.append(len(names))
            clusters = hploc_list_merge(clusters, 1 if root else HPLOC_THRESHOLD,
                                        HPLOC_RADIUS, names)
        labels.append((first, last, depth, [name for name, _ in clusters],
                       merged and len(clusters) < len(left_list) + len(right_list)))
        return clusters, max(left_depth, right_depth) + 1

    _, height = walk(tree, 0)
    fig, (plane, ax) = plt.subplots(1, 2, figsize=(15, 6.2),
                                    gridspec_kw={"width_ratios": [1, 1.9]})
    plane.set_aspect("equal")
    plane.set_xticks([])
    plane.set_yticks([])
    plane.plot([p[0] for p in points], [p[1] for p in points], color="#cccccc", linewidth=1,
               zorder=0)
    for k, (x, y) in enumerate(points):
        plane.plot(x, y, "o", color=GREY, markersize=4)
        plane.text(x + 0.08, y + 0.08, str(k), fontsize=8, color=GREY)
    for made, (node, ((x0, y0), (x1, y1))) in enumerate(names.items()):
        if made >= root_first[0]:
            break  # the root's own merges span everything: left out
        grow = 0.1 + 0.04 * made
        plane.add_patch(Rectangle((x0 - grow, y0 - grow), x1 - x0 + 2 * grow,
                                  y1 - y0 + 2 * grow, fill=False, edgecolor=RED,
                                  linewidth=1))
        plane.text(x0 - grow, y1 + grow, node, fontsize=8, color=RED, va="bottom")
    plane.set_title("The points in Morton order (grey line) and the nodes\nmerged below the "
                    "root (red)", fontsize=10)
    ax.axis("off")
    ax.set_xlim(-0.8, len(points) - 0.2)
    ax.set_ylim(-1.4, height + 0.9)
    for k in range(len(points)):
        ax.text(k, 0, str(k), ha="center", va="center", fontsize=9,
                bbox=dict(boxstyle="round,pad=0.25", facecolor="#eef5fb", edgecolor=BLUE))
    place = {}
    for first, last, depth, clusters, merged in labels:
        place[(first, last)] = ((first + last) / 2, height - depth)
    for first, last, depth, clusters, merged in labels:
        x, y = place[(first, last)]
        ax.text(x, y, " ".join(clusters), ha="center", va="center", fontsize=8.5,
                family="monospace", color=RED if merged else "black",
                bbox=dict(boxstyle="round,pad=0.25", facecolor="#fdf2e9" if merged else "white",
                          edgecolor=RED if merged else GREY))
    for first, last, depth, clusters, merged in labels:  # each node to its two children
        x, y = place[(first, last)]
        for child in [c for c in place if c != (first, last) and first <= c[0] and
                      c[1] <= last and place[c][1] == y - 1]:
            ax.plot([x, place[child][0]], [y - 0.2, place[child][1] + 0.2], color=GREY,
                    linewidth=0.8, zorder=0)
        ranges = [c for c in place if first <= c[0] and c[1] <= last and c != (first, last)]
        for k in range(first, last + 1):  # leaves hang from the lowest node above them
            if all(not (c[0] <= k <= c[1]) for c in ranges):
                ax.plot([x, k], [y - 0.2, 0.25], color=GREY, linewidth=0.8, zorder=0)
    ax.set_title(f"Each subtree's list, passed up (at most {HPLOC_THRESHOLD} clusters; "
                 f"PLOC within {HPLOC_RADIUS} places where it grows past them, red)",
                 fontsize=10)
    fig.text(0.5, 0.01, "Leaves are numbered in Morton order; A, B, ... are the nodes the "
             "merges made, in the order made. A subtree of at most three points passes its "
             "leaves up unmerged;\nabove that, the two lists side by side are merged down to "
             "three, and at the root down to one: the root of the whole tree.",
             ha="center", fontsize=9.5, color=GREY)
    save(fig, out / "10_hploc_walk.svg")
    plt.close(fig)


# Seven boxes in the plane (x0, y0, x1, y1) under one treelet root, and the chain that joined
# them in the order given: each interior node the one before and the next box.
TREELET_BOXES = [(0.0, 0.0, 1.0, 1.2), (5.2, 0.3, 6.0, 1.0), (0.6, 2.2, 1.6, 3.0),
                 (5.6, 2.4, 6.6, 3.3), (2.6, 0.2, 3.4, 0.9), (0.2, 1.1, 0.9, 2.0),
                 (6.0, 1.2, 6.8, 2.2)]


def union(boxes):
    return (min(b[0] for b in boxes), min(b[1] for b in boxes), max(b[2] for b in boxes),
            max(b[3] for b in boxes))


def perimeter(box):  # the plane's half surface area: half the perimeter
    return (box[2] - box[0]) + (box[3] - box[1])


def treelet_search(boxes):
    """treelets.h's search: the least total size of the interior boxes of any tree over each
    subset, and the part holding the subset's lowest leaf in its best split."""
    count = len(boxes)
    cost, split = {}, {}
    for s in range(1, 1 << count):
        size = perimeter(union([boxes[i] for i in range(count) if s >> i & 1]))
        lowest = s & -s
        rest = s ^ lowest
        if rest == 0:
            cost[s] = 0.0
            continue
        best, best_part, q = None, 0, rest
        while q:
            q = (q - 1) & rest
            part = lowest | q
            c = cost[part] + cost[s ^ part]
            if best is None or c < best:
                best, best_part = c, part
        cost[s], split[s] = size + best, best_part
    return cost, split


def treelet_plot(out):
    """A treelet's seven leaves joined as a chain, and the same leaves in the tree the search
    finds: each interior node's box drawn, its size (the plane's half area) summed below."""
    count = len(TREELET_BOXES)
    chain = [sum(1 << i for i in range(k + 1)) for k in range(1, count)]  # 0+1, 0+1+2, ...
    cost, split = treelet_search(TREELET_BOXES)
    best = []

    def collect(s):
        if s & (s - 1):
            best.append(s)
            collect(split[s])
            collect(s ^ split[s])

    collect((1 << count) - 1)
    fig, axes = plt.subplots(1, 2, figsize=(13, 4.6))
    for ax, sets, title in ((axes[0], chain, "as the clustering left them: a chain"),
                            (axes[1], best, "after the search: the least total size")):
        ax.set_aspect("equal")
        ax.axis("off")
        ax.set_xlim(-0.9, 7.6)
        ax.set_ylim(-0.9, 4.1)
        for k, b in enumerate(TREELET_BOXES):
            ax.add_patch(Rectangle((b[0], b[1]), b[2] - b[0], b[3] - b[1], facecolor="#eef5fb",
                                   edgecolor=BLUE, linewidth=1))
            ax.text((b[0] + b[2]) / 2, (b[1] + b[3]) / 2, str(k), ha="center", va="center",
                    fontsize=9, color=BLUE)
        total = 0.0
        for depth, s in enumerate(sorted(sets, key=lambda s: -bin(s).count("1"))):
            b = union([TREELET_BOXES[i] for i in range(count) if s >> i & 1])
            grow = 0.07 * (bin(s).count("1") - 1)
            ax.add_patch(Rectangle((b[0] - grow, b[1] - grow), b[2] - b[0] + 2 * grow,
                                   b[3] - b[1] + 2 * grow, fill=False, edgecolor=RED,
                                   linewidth=1))
            total += perimeter(b)
        ax.set_title(f"{title}\nsix interior boxes, total size {total:.1f}", fontsize=10)
    fig.text(0.5, 0.02, "The same seven leaves (blue: subtrees kept whole) under the same root. "
             "Only the five boxes between them and the root change; the search tries every "
             "tree over the leaves\n(10 395 of them) in 966 steps, by the best tree over "
             "every subset, and the root's box and every subtree below the leaves stay as "
             "they were.", ha="center", fontsize=9.5, color=GREY)
    save(fig, out / "10_treelet.svg")
    plt.close(fig)


# A made-up binary subtree under one wide node R, with made-up choices (the sah rule's shares):
# (name, x, y, parent, side, share given, what it becomes). R gives its sides 1 and 3; A, given
# one child, is a leaf; B shares its three as 1 and 2; C, given one, is a wide node; D shares
# its two as 1 and 1, E a binary leaf and F a leaf of its triangles. G lies below the leaf A.
SHARE_NODES = (
    ("R", 4.0, 4.0, None, None, 4, "wide"),
    ("A", 1.6, 3.0, "R", "left", 1, "leaf"),
    ("B", 6.0, 3.0, "R", "right", 3, "open"),
    ("G", 1.0, 2.0, "A", "left", None, "below"),
    ("C", 4.4, 2.0, "B", "left", 1, "wide"),
    ("D", 7.4, 2.0, "B", "right", 2, "open"),
    ("E", 6.6, 1.0, "D", "left", 1, "binary leaf"),
    ("F", 8.3, 1.0, "D", "right", 1, "leaf"),
)


def collapse_shares(out):
    """How the sah rule finds the children of the wide node R: shares handed down (numbers on
    the links), nodes opened (grey), the four children (blue leaves, a red wide node)."""
    fig, ax = plt.subplots(figsize=(10, 4.6))
    ax.axis("off")
    ax.set_xlim(-0.2, 11.6)
    ax.set_ylim(0.3, 4.7)
    at = {name: (x, y) for name, x, y, *_ in SHARE_NODES}
    colours = {"wide": RED, "leaf": BLUE, "binary leaf": BLUE, "open": GREY, "below": "#bbbbbb"}
    for name, x, y, parent, side, share, kind in SHARE_NODES:
        if parent:
            px, py = at[parent]
            ax.plot([px, x], [py, y], color="#999999", linewidth=1, zorder=1)
            if share is not None:
                ax.text((px + x) / 2 + (-0.22 if side == "left" else 0.22), (py + y) / 2,
                        str(share), ha="center", va="center", fontsize=11, color=GREEN,
                        fontweight="bold")
        shape = "square,pad=0.25" if kind in ("leaf", "binary leaf") else "circle,pad=0.25"
        ax.text(x, y, name, ha="center", va="center", fontsize=11, color="white", zorder=2,
                bbox=dict(boxstyle=shape, facecolor=colours[kind], edgecolor="none"))
    notes = (
        (4.0, 4.45, "R: a wide node, four children to hand out: 1 to the left, 3 to the right"),
        (2.75, 2.55, "A: one child, a leaf\n(cheaper than a wide node)"),
        (6.85, 3.35, "B: three, shared again: 1 + 2"),
        (1.0, 1.45, "G: below a leaf,\nnever a wide node"),
        (4.4, 1.45, "C: one child, a wide node\n(its own four come later)"),
        (8.25, 2.35, "D: two, shared: 1 + 1"),
        (7.45, 0.45, "E, F: one each, leaves"),
    )
    for x, y, text in notes:
        ax.text(x, y, text, ha="center", va="center", fontsize=8.5, color=GREY)
    ax.text(9.9, 3.4, "C's walk: climbing C, B, R\nit notes left, right;\nwalking down it "
            "replays\nR's 3 to the right, B's 1\nto the left: C is given\none child, and "
            "it is\nnot a leaf: a wide node", ha="center", va="center", fontsize=8.5,
            color=RED)
    fig.text(0.5, 0.02, "Made-up shares on a made-up subtree. R's children are A (a leaf), C (a "
             "wide node), E and F (leaves); B and D are opened and disappear. A node given s "
             "children first takes fewer\nwhile fewer cost no more; every node finds its own "
             "fate by walking its one path from the root, so all of them do it at once.",
             ha="center", fontsize=9, color=GREY)
    save(fig, out / "10_collapse_shares.svg")
    plt.close(fig)


def main():
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "book" / "images"
    out.mkdir(parents=True, exist_ok=True)
    morton_curve(out)
    karras_split(out)
    karras_tree(out)
    ploc_merges(out)
    hploc_walk(out)
    treelet_plot(out)
    collapse_shares(out)
    animation_plot(out)
    for csv_name, scene, png_name in GPU_ANIMATIONS:
        gpu_animation_plot(out, csv_name, scene, png_name)


if __name__ == "__main__":
    main()
