#!/usr/bin/env python3
"""Chapter 13's diagrams (book/images/13_*): one mesh in its own space and placed in the world,
with a ray in both spaces and the same t marked on each; the top-level tree over the boxes of a
few placed meshes (an LBVH: Morton order, split at the highest differing bit); the two-level
walk, from a top-level leaf through the transform and the bottom-level tree back to the hit;
and what flattening does to a small sphere far from the origin, its vertices rounded to float
in numpy as chapter 13's flatten() rounds them.

  tools/diagrams/ch13.py [OUT_DIR]     (default: book/images)
"""
import math
import sys
from pathlib import Path

import matplotlib

matplotlib.use("svg")
matplotlib.rcParams["svg.hashsalt"] = "rt-course-ch13"  # the same file on every run
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.patches import FancyArrowPatch, FancyBboxPatch, Polygon, Rectangle  # noqa: E402

BLUE, GREY, RED, GREEN, ORANGE = "#2a7ab0", "#555555", "#c0392b", "#2e8b57", "#d35400"
ROOT = Path(__file__).resolve().parents[2]

# A little tree in its own space: a trunk and a crown, the outline of a 2D "mesh".
TREE = [(-0.15, 0.0), (0.15, 0.0), (0.15, 0.6), (0.8, 0.6), (0.0, 2.0), (-0.8, 0.6),
        (-0.15, 0.6)]
# A rock: the other mesh of the top-level picture.
ROCK = [(-0.6, 0.0), (0.6, 0.0), (0.7, 0.35), (0.2, 0.7), (-0.45, 0.55)]


def save(fig, path):
    fig.savefig(path, format="svg", metadata={"Date": None}, bbox_inches="tight")


def affine(angle_degrees, scale, tx, ty):
    """A 2 x 3 matrix, rows as in chapter 13's Affine: rotate, scale, then translate."""
    a = math.radians(angle_degrees)
    c, s = math.cos(a) * scale, math.sin(a) * scale
    return np.array([[c, -s, tx], [s, c, ty]])


def inverse(m):
    linear = np.linalg.inv(m[:, :2])
    return np.hstack([linear, (-linear @ m[:, 2]).reshape(2, 1)])


def point(m, p):
    return m[:, :2] @ np.asarray(p, dtype=float) + m[:, 2]


def direction(m, d):
    return m[:, :2] @ np.asarray(d, dtype=float)


def first_hit(outline, origin, d):
    """The smallest t > 0 at which origin + t d crosses the closed outline."""
    best = math.inf
    for k in range(len(outline)):
        a, b = np.array(outline[k]), np.array(outline[(k + 1) % len(outline)])
        e = b - a
        det = d[0] * -e[1] + d[1] * e[0]
        if abs(det) < 1e-12:
            continue
        r = a - origin
        t = (r[0] * -e[1] + r[1] * e[0]) / det
        s = (d[0] * r[1] - d[1] * r[0]) / det
        if t > 1e-9 and 0.0 <= s <= 1.0:
            best = min(best, t)
    return best


def spaces(out):
    """The tree in its own space and placed in the world by a turn, a scale and a move; the
    world ray and its copy in object space (origin and direction through the inverse, the
    direction not normalised), with t = 1, 2, 3 and the hit marked on both."""
    to_world = affine(35.0, 1.6, 4.0, 1.0)
    to_object = inverse(to_world)
    origin, d = np.array([0.3, 3.6]), np.array([0.9, -0.45])
    world_outline = [point(to_world, p) for p in TREE]
    t_hit = first_hit(world_outline, origin, d)
    local_origin, local_d = point(to_object, origin), direction(to_object, d)
    fig, (left, right) = plt.subplots(1, 2, figsize=(12, 5.2))
    panels = ((left, TREE, local_origin, local_d, "object space: the mesh as it was modelled",
               "ray in object space: o' = M⁻¹ o, d' = M⁻¹ d"),
              (right, world_outline, origin, d, "world space: the mesh placed by M (turn 35°, "
               "scale 1.6, move)", "ray in world space: o, d"))
    for ax, outline, o, dd, title, label in panels:
        ax.add_patch(Polygon(outline, closed=True, facecolor="#d8ecd8", edgecolor=GREEN,
                             linewidth=1.5))
        end = o + (t_hit + 0.8) * dd
        ax.annotate("", xy=end, xytext=o, arrowprops=dict(arrowstyle="-|>", color=BLUE,
                                                           linewidth=1.5))
        ax.plot(*o, "o", color=BLUE)
        ax.text(o[0], o[1] + 0.15, label, fontsize=9, color=BLUE)
        for t in (1, 2, 3):
            p = o + t * dd
            ax.plot(*p, "|", color=BLUE, markersize=10, markeredgewidth=1.5)
            ax.text(p[0], p[1] - 0.32, f"t={t}", fontsize=8, color=BLUE, ha="center")
        hit = o + t_hit * dd
        ax.plot(*hit, "o", color=RED, markersize=7)
        ax.text(hit[0] + 0.12, hit[1] + 0.1, f"hit, t = {t_hit:.3f}", fontsize=9, color=RED)
        ax.set_title(title, fontsize=10)
        ax.set_aspect("equal")
        ax.grid(color="#eeeeee")
        ax.tick_params(labelsize=8)
    # The world origin's axes, and where the object's own axes went.
    ex, ey = direction(to_world, (1, 0)), direction(to_world, (0, 1))
    base = point(to_world, (0, 0))
    for v, name in ((ex, "x'"), (ey, "y'")):
        right.annotate("", xy=base + v, xytext=base,
                       arrowprops=dict(arrowstyle="->", color=GREY, linewidth=1))
        right.text(*(base + 1.08 * v), name, fontsize=8, color=GREY)
    left.set_xlim(-2.2, 2.4)
    left.set_ylim(-1.6, 2.9)
    right.set_xlim(-0.2, 7.6)
    right.set_ylim(-0.6, 4.6)
    fig.text(0.5, -0.02, "The ray goes to the mesh, not the mesh to the ray: two points and a "
             "direction through M⁻¹ instead of every vertex through M. The direction is not "
             "made unit length again,\nso the tick marks fall on the same places of the mesh in "
             f"both spaces and the hit has the same t (its length is {np.linalg.norm(local_d):.3f}"
             f" in object space, {np.linalg.norm(d):.3f} in the world).", ha="center",
             fontsize=9, color=GREY)
    save(fig, out / "13_spaces.svg")
    plt.close(fig)


# The placed meshes of the top-level picture: (mesh, turn in degrees, scale, x, y).
PLACEMENTS = [(0, 0, 1.0, 1.0, 0.3), (0, 20, 0.8, 3.2, 0.2), (1, 0, 1.0, 5.0, 0.2),
              (0, -15, 1.2, 7.4, 0.4), (1, 30, 0.9, 2.2, 3.2), (0, 10, 0.9, 4.4, 3.0),
              (0, 0, 1.1, 6.6, 3.1), (1, -20, 1.2, 8.6, 3.3)]
MESH_NAMES = ("tree", "rock")


def box_of(points):
    xs, ys = [p[0] for p in points], [p[1] for p in points]
    return (min(xs), min(ys)), (max(xs), max(ys))


def join(a, b):
    return ((min(a[0][0], b[0][0]), min(a[0][1], b[0][1])),
            (max(a[1][0], b[1][0]), max(a[1][1], b[1][1])))


def spread2(x):
    """The 4 low bits of x with a zero bit between them (2D Morton, as morton.h does in 3D)."""
    out = 0
    for bit in range(4):
        out |= ((x >> bit) & 1) << (2 * bit)
    return out


def lbvh(codes, first, last):
    """The LBVH's hierarchy over sorted codes: a range splits where the highest bit in which
    its first and last codes differ turns from 0 to 1 (equal codes split in the middle)."""
    if first == last:
        return first
    x = codes[first] ^ codes[last]
    if x == 0:
        split = (first + last) // 2
    else:
        bit = x.bit_length() - 1
        split = first
        while (codes[split + 1] >> bit) & 1 == 0:
            split += 1
    return (lbvh(codes, first, split), lbvh(codes, split + 1, last))


def top_level(out):
    """Eight instances of two meshes, their world boxes, the top level's node boxes, and the
    binary tree above them with an instance in every leaf."""
    instances = []
    for mesh, turn, scale, x, y in PLACEMENTS:
        m = affine(turn, scale, x, y)
        outline = [point(m, p) for p in (TREE if mesh == 0 else ROCK)]
        instances.append((mesh, outline, box_of(outline)))
    centres = [((b[0][0] + b[1][0]) / 2, (b[0][1] + b[1][1]) / 2) for _, _, b in instances]
    lo = [min(c[a] for c in centres) for a in range(2)]
    hi = [max(c[a] for c in centres) for a in range(2)]
    cells = [tuple(min(15, int((c[a] - lo[a]) / (hi[a] - lo[a]) * 16)) for a in range(2))
             for c in centres]
    codes = [spread2(x) << 1 | spread2(y) for x, y in cells]
    order = sorted(range(len(instances)), key=lambda k: (codes[k], k))
    tree = lbvh([codes[k] for k in order], 0, len(order) - 1)

    fig, (plane, ax) = plt.subplots(1, 2, figsize=(15, 5.6),
                                    gridspec_kw={"width_ratios": [1.25, 1]})
    node_boxes = []

    def box_walk(node, depth):
        if isinstance(node, int):
            return instances[order[node]][2]
        box = join(box_walk(node[0], depth + 1), box_walk(node[1], depth + 1))
        node_boxes.append((depth, box))
        return box

    box_walk(tree, 0)
    for k, (mesh, outline, ((x0, y0), (x1, y1))) in enumerate(instances):
        plane.add_patch(Polygon(outline, closed=True, facecolor="#d8ecd8" if mesh == 0
                                else "#eadccb", edgecolor=GREEN if mesh == 0 else ORANGE))
        plane.add_patch(Rectangle((x0, y0), x1 - x0, y1 - y0, fill=False, edgecolor=BLUE,
                                  linewidth=1.2))
        plane.text(x0, y1 + 0.05, f"instance {k}", fontsize=7.5, color=BLUE)
    for depth, ((x0, y0), (x1, y1)) in node_boxes:
        grow = 0.12 + 0.1 * (3 - depth)
        plane.add_patch(Rectangle((x0 - grow, y0 - grow), x1 - x0 + 2 * grow,
                                  y1 - y0 + 2 * grow, fill=False, edgecolor=RED,
                                  linewidth=0.9, linestyle="--"))
    plane.set_aspect("equal")
    plane.set_xticks([])
    plane.set_yticks([])
    plane.autoscale_view()
    plane.set_title("Eight instances of two meshes: each instance's world box (blue)\nand the "
                    "top level's node boxes around them (red, dashed)", fontsize=10)

    # The tree: leaves in Morton order along the bottom, each interior node above its range.
    ax.axis("off")
    positions = {}

    def place(node, depth):
        if isinstance(node, int):
            positions[("leaf", node)] = (node, 0.0)
            return node, node, 0
        a_lo, a_hi, a_h = place(node[0], depth + 1)
        b_lo, b_hi, b_h = place(node[1], depth + 1)
        height = max(a_h, b_h) + 1
        positions[id(node)] = ((a_lo + b_hi) / 2, float(height))
        return a_lo, b_hi, height

    def key(node):
        return ("leaf", node) if isinstance(node, int) else id(node)

    def draw(node):
        x, y = positions[key(node)]
        if isinstance(node, int):
            k = order[node]
            ax.add_patch(FancyBboxPatch((x - 0.42, y - 0.35), 0.84, 0.7,
                                        boxstyle="round,pad=0.02", facecolor="#eef5fb",
                                        edgecolor=BLUE))
            ax.text(x, y + 0.1, f"inst. {k}", ha="center", fontsize=8, color=BLUE)
            ax.text(x, y - 0.17, MESH_NAMES[instances[k][0]], ha="center", fontsize=7.5,
                    color=GREEN if instances[k][0] == 0 else ORANGE)
            return
        for child in node:
            cx, cy = positions[key(child)]
            ax.plot([x, cx], [y - 0.2, cy + 0.36], color=GREY, linewidth=1)
            draw(child)
        ax.plot(x, y, "s", color=RED, markersize=8)

    place(tree, 0)
    draw(tree)
    top = max(y for _, y in positions.values())
    for mesh, colour in ((0, GREEN), (1, ORANGE)):
        ax.add_patch(FancyBboxPatch((1.5 + 3.2 * mesh, -2.1), 2.6, 0.8,
                                    boxstyle="round,pad=0.05", facecolor="white",
                                    edgecolor=colour))
        ax.text(2.8 + 3.2 * mesh, -1.7, f"{MESH_NAMES[mesh]}'s own tree\n(4-wide, built once)",
                ha="center", va="center", fontsize=8, color=colour)
    for n, k in enumerate(order):
        mesh = instances[k][0]
        ax.annotate("", xy=(2.8 + 3.2 * mesh, -1.3), xytext=(n, -0.37),
                    arrowprops=dict(arrowstyle="->", color="#bbbbbb", linewidth=0.8))
    ax.set_xlim(-0.8, len(order) - 0.2)
    ax.set_ylim(-2.4, top + 0.6)
    ax.set_title("The top level: a binary tree (chapter 10's LBVH) with an instance in every "
                 "leaf;\nbelow it, the two bottom-level trees the leaves share", fontsize=10)
    save(fig, out / "13_top_level.svg")
    plt.close(fig)


def walk(out):
    """The two-level walk as boxes and arrows: the top level's binary walk, an instance at a
    leaf, the ray through to_object, the mesh's 4-wide walk with the nearest t so far as its
    tmax, and the hit coming back to shorten the rest of the top-level walk."""
    fig, ax = plt.subplots(figsize=(13, 5.4))
    ax.set_xlim(0, 13)
    ax.set_ylim(0, 5.6)
    ax.axis("off")

    def box(x, y, w, h, text, colour, face):
        ax.add_patch(FancyBboxPatch((x, y), w, h, boxstyle="round,pad=0.08", facecolor=face,
                                    edgecolor=colour, linewidth=1.3))
        ax.text(x + w / 2, y + h / 2, text, ha="center", va="center", fontsize=8.8,
                color="black")

    def arrow(a, b, text="", colour=GREY, offset=(0.0, 0.12), style="-|>", rad=0.0):
        ax.add_patch(FancyArrowPatch(a, b, arrowstyle=style, mutation_scale=12, color=colour,
                                     linewidth=1.3, connectionstyle=f"arc3,rad={rad}"))
        if text:
            ax.text((a[0] + b[0]) / 2 + offset[0], (a[1] + b[1]) / 2 + offset[1], text,
                    ha="center", fontsize=8, color=colour)

    box(0.2, 3.6, 3.2, 1.5, "top level: chapter 07's binary walk\nover instance boxes, world "
        "ray\n(nearer child first, the other\non the stack)", RED, "#fbeeee")
    box(4.6, 3.6, 3.4, 1.5, "leaf: instance k\nmask test: (ray mask & k's mask) ≠ 0?\n"
        "k's to_object (3 x 4, float)", BLUE, "#eef5fb")
    box(9.2, 3.6, 3.6, 1.5, "object-space ray\no' = to_object · o\nd' = to_object · d "
        "(not normalised)\ntmin, tmax unchanged", BLUE, "#eef5fb")
    box(9.2, 0.5, 3.6, 1.6, "bottom level: chapter 09's\n4-wide walk of mesh m's tree,\n"
        "chapter 04's watertight test,\ntmax = the nearest hit so far", GREEN, "#e8f4ec")
    box(4.6, 0.5, 3.4, 1.6, "a nearer hit?\nhit = (k, triangle, t, u, v)\nworld ray's tmax = t",
        ORANGE, "#fbf0e6")
    box(0.2, 0.5, 3.2, 1.6, "closest hit: go on, with the\nshorter tmax cutting off farther\n"
        "boxes and instances\nany hit: stop here", RED, "#fbeeee")
    arrow((3.45, 4.35), (4.55, 4.35), "a leaf's box is entered")
    arrow((8.05, 4.35), (9.15, 4.35), "two points' worth\nof arithmetic", offset=(0, 0.15))
    arrow((11.0, 3.55), (11.0, 2.15), "the same t\non both rays", offset=(0.75, -0.05))
    arrow((9.15, 1.3), (8.05, 1.3), "t, triangle,\nu, v", offset=(0, 0.12))
    arrow((4.55, 1.3), (3.45, 1.3), "")
    arrow((1.8, 2.15), (1.8, 3.55), "back to the stack", offset=(-0.75, -0.05))
    arrow((6.3, 3.55), (2.6, 2.2), "mask says no,\nor no nearer hit in k", colour="#888888",
          offset=(0.9, 0.1), rad=0.0)
    ax.text(6.5, 5.4, "One RT_HD function, both backends: the world ray never changes except "
            "its tmax, which only ever shrinks", ha="center", fontsize=9.5, color=GREY)
    save(fig, out / "13_walk.svg")
    plt.close(fig)


def icosphere(levels):
    """The unit icosphere: an icosahedron's faces split in four `levels` times, the new
    vertices pushed out to the sphere (320 triangles and 162 vertices for two levels)."""
    g = (1.0 + math.sqrt(5.0)) / 2.0
    vertices = [(-1, g, 0), (1, g, 0), (-1, -g, 0), (1, -g, 0), (0, -1, g), (0, 1, g),
                (0, -1, -g), (0, 1, -g), (g, 0, -1), (g, 0, 1), (-g, 0, -1), (-g, 0, 1)]
    vertices = [np.array(v, dtype=float) / np.linalg.norm(v) for v in vertices]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9),
             (5, 11, 4), (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6),
             (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(levels):
        middle = {}

        def mid(a, b):
            key = (min(a, b), max(a, b))
            if key not in middle:
                v = vertices[a] + vertices[b]
                vertices.append(v / np.linalg.norm(v))
                middle[key] = len(vertices) - 1
            return middle[key]

        split = []
        for a, b, c in faces:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            split += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = split
    return np.array(vertices), faces


# Where the small spheres stand: about 10^5 from the origin on every axis, off the float grid.
FAR = np.array([100000.3, 100000.55, 99999.8])


def origin_error(turns=3, eyes=2000):
    """The camera ray's origin moved into the space of far_away()'s sphere scaled by 10^-3 at
    FAR, in float, as to_object_space does it: the instance's translation (stored in float)
    subtracted first, then turned and scaled by to_object's linear part (three products and
    two sums per row, each rounded, no fused multiply-add). Eyes within about 0.05 of the
    sphere, random turns. Returns, in object units (the sphere's radius is 1), how far the
    translation's rounding moves the whole sphere (the same for every ray), and the median and
    largest distance of each moved origin from exact for the sphere so moved."""
    random = np.random.default_rng(13)
    shifts, errors = [], []
    for _ in range(turns):
        q = random.normal(size=4)
        a, b, c, d = q / np.linalg.norm(q)
        turn = np.array([[a * a + b * b - c * c - d * d, 2 * (b * c - a * d), 2 * (b * d + a * c)],
                         [2 * (b * c + a * d), a * a - b * b + c * c - d * d, 2 * (c * d - a * b)],
                         [2 * (b * d - a * c), 2 * (c * d + a * b), a * a - b * b - c * c + d * d]])
        inverse_linear = np.linalg.inv(1e-3 * turn)  # in double, rounded once, as
        m32 = inverse_linear.astype(np.float32)       # placed_instance does
        t32 = FAR.astype(np.float32)                  # to_world's translation, in float
        shifts.append(float(np.linalg.norm(inverse_linear @ (t32.astype(np.float64) - FAR))))
        for _ in range(eyes):
            eye = (FAR + random.normal(size=3) * 0.05).astype(np.float32)
            local = [np.float32(eye[k] - t32[k]) for k in range(3)]  # exact: Sterbenz
            moved = []
            for r in range(3):
                s = np.float32(m32[r, 0] * local[0])
                s = np.float32(s + np.float32(m32[r, 1] * local[1]))
                moved.append(float(np.float32(s + np.float32(m32[r, 2] * local[2]))))
            exact = inverse_linear @ (eye.astype(np.float64) - t32.astype(np.float64))
            errors.append(float(np.linalg.norm(np.array(moved) - exact)))
    return max(shifts), float(np.median(errors)), max(errors)


def far_away(out):
    """A 320-triangle sphere of radius r placed at FAR: in its own space (every digit kept, as
    an instance keeps it), and flattened (each vertex placed in double and rounded once to
    float32, as flatten() does) for r = 0.05, 0.01 and 0.001, seen along z, with the float
    grid around FAR and the exact sphere's outline (dashed)."""
    unit, faces = icosphere(2)
    shift, median, largest = origin_error()
    ulp = float(np.spacing(np.float32(FAR[0])))
    fig, axes = plt.subplots(1, 4, figsize=(16, 4.6))
    front = [f for f in faces if unit[list(f)].mean(axis=0)[2] > 0.0]  # the half facing us

    def wire(ax, v, colour):
        for a, b, c in front:
            ax.plot([v[a][0], v[b][0], v[c][0], v[a][0]], [v[a][1], v[b][1], v[c][1], v[a][1]],
                    color=colour, linewidth=0.6)

    wire(axes[0], unit, GREEN)
    axes[0].set_title(f"In its own space (an instance):\n{len(unit)} vertices, "
                      f"{len(faces)} triangles, radius 1", fontsize=9.5)
    axes[0].set_xlim(-1.3, 1.3)
    axes[0].set_ylim(-1.3, 1.3)
    for ax, radius in zip(axes[1:], (0.05, 0.01, 0.001)):
        exact = FAR + radius * unit  # the placement in double
        snapped = exact.astype(np.float32).astype(np.float64)  # rounded once to float
        distinct = len({tuple(v) for v in snapped})
        # Seen relative to the sphere's centre, in units of its radius.
        rel = (snapped - FAR) / radius
        lo = math.floor((FAR[0] - 1.3 * radius) / ulp) * ulp
        hi_x = FAR[0] + 1.3 * radius
        lines = 0
        x = lo
        while x <= hi_x and lines < 80:
            ax.axvline((x - FAR[0]) / radius, color="#dddddd", linewidth=0.6, zorder=0)
            x += ulp
            lines += 1
        y = math.floor((FAR[1] - 1.3 * radius) / ulp) * ulp
        while y <= FAR[1] + 1.3 * radius and lines < 160:
            ax.axhline((y - FAR[1]) / radius, color="#dddddd", linewidth=0.6, zorder=0)
            y += ulp
            lines += 1
        ax.add_patch(plt.Circle((0, 0), 1.0, fill=False, edgecolor=GREEN, linewidth=1.0,
                                linestyle="--"))
        wire(ax, rel, RED)
        ax.plot(rel[:, 0], rel[:, 1], ".", color=RED, markersize=3)
        ax.set_xlim(-1.3 if radius > 0.005 else -1.3 * ulp / radius,
                    1.3 if radius > 0.005 else 1.3 * ulp / radius)
        ax.set_ylim(ax.get_xlim())
        ax.set_title(f"Flattened, radius {radius:g} at 10⁵ (scale {radius:g}):\n{distinct} "
                     f"distinct vertices of {len(unit)} left", fontsize=9.5)
    for ax in axes:
        ax.set_aspect("equal")
        ax.set_xticks([])
        ax.set_yticks([])
    fig.text(0.5, -0.04, f"Near 10⁵ a float is a multiple of {ulp} (grey lines: the float grid, "
             "drawn in units of each sphere's radius; dashed: the exact sphere). Flattening "
             "places every vertex there and rounds it to that grid:\nat radius 0.05 the sphere "
             "is lumpy, at 0.01 a cross of five grid squares, at 0.001 (the smallest scale "
             "chapter 13 accepts) a handful of points. The instance keeps the first panel's "
             "mesh;\nits translation, rounded to float, moves the whole sphere by at most "
             f"{shift:.1f} radii, the same for every ray, and each ray's origin moved into its "
             f"space lands a median {median:.1e} and at most {largest:.1e} radii from exact "
             "(2 000 eyes, 3 turns).", ha="center", fontsize=9, color=GREY)
    save(fig, out / "13_far_away.svg")
    plt.close(fig)


def main():
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "book" / "images"
    out.mkdir(parents=True, exist_ok=True)
    spaces(out)
    top_level(out)
    walk(out)
    far_away(out)


if __name__ == "__main__":
    main()
