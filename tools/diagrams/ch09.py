#!/usr/bin/env python3
"""Chapter 09's diagrams, in book/images:
  09_compressed_node.svg  the compressed wide node of chapters/09_wide_bvh/wide_bvh.h
                          (CompressedNode), 80 bytes read as five 16-byte records, byte by byte
  09_collapse.svg         a binary subtree cut into eight pieces: one wide node's children
  09_quantised_box.svg    a child box rounded outward onto its parent's power-of-two grid
  09_octant_order.svg     the ray's direction signs choosing the order of the children's slots
  09_warp_lanes.svg       a warp's lanes busy and idle, binary against wide (an illustration)
  09_warp_variants.svg    the three ways to keep a warp busy, measured on an H200
                          (book/data/09_benchmark_h200.json)

  tools/diagrams/ch09.py [OUT_DIR] [DATA_DIR]     (defaults: book/images, book/data)
"""
import json
import sys
from pathlib import Path

import matplotlib

matplotlib.use("svg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import Rectangle  # noqa: E402

GREY = "#555555"
# One colour per kind of field: the grid (origin, exponents), the child mask, the links, the
# meta bytes, and the quantised lo and hi planes.
ORIGIN, EXPONENT, MASK, LINK = "#cfe2f3", "#f9cb9c", "#d9d2e9", "#d9ead3"
META, PLANE_LO, PLANE_HI = "#fff2cc", "#ead1dc", "#f4cccc"

# The node's fields as (first byte, bytes, label, colour), in the order of the struct: the
# offsets are the ones its static_asserts hold (exponent 12, imask 15, child_base 16, meta 24,
# q_lo_x 32, q_hi_x 56). Eight children, one byte each per plane.
FIELDS = [
    (0, 4, "origin.x", ORIGIN), (4, 4, "origin.y", ORIGIN), (8, 4, "origin.z", ORIGIN),
    (12, 1, "e.x", EXPONENT), (13, 1, "e.y", EXPONENT), (14, 1, "e.z", EXPONENT),
    (15, 1, "imask", MASK),
    (16, 4, "child_base", LINK), (20, 4, "triangle_base", LINK),
    (24, 8, "meta[0..7]", META),
    (32, 8, "q_lo_x[0..7]", PLANE_LO), (40, 8, "q_lo_y[0..7]", PLANE_LO),
    (48, 8, "q_lo_z[0..7]", PLANE_LO),
    (56, 8, "q_hi_x[0..7]", PLANE_HI), (64, 8, "q_hi_y[0..7]", PLANE_HI),
    (72, 8, "q_hi_z[0..7]", PLANE_HI),
]
NODE_BYTES = 80
RECORD_BYTES = 16  # one 16-byte load

NOTES = [
    ("origin", "the node box's lo corner (float32)."),
    ("e", "the grid step along each axis, 2^(e - 127): a float's exponent bits."),
    ("imask", "bit s set where slot s holds an interior child."),
    ("child_base", "its first interior child; the others follow in slot order."),
    ("triangle_base", "the first triangle record of its leaves."),
    ("meta", "per child: 0 = empty;  001 11sss = interior child in octant slot s;\n"
             "ccc ooooo = a leaf of 1 to 3 triangles (ccc in unary) at offset ooooo from "
             "triangle_base."),
    ("q_lo, q_hi", "per child and axis, 8-bit grid planes rounded outward:\n"
                   "q_lo * step + origin <= the child's exact lo, q_hi * step + origin >= its "
                   "exact hi,\nin the traversal's own float arithmetic."),
]


def save(fig, path):
    fig.savefig(path, format="svg", metadata={"Date": None}, bbox_inches="tight")


def compressed_node(out):
    assert sum(size for _, size, _, _ in FIELDS) == NODE_BYTES
    records = NODE_BYTES // RECORD_BYTES
    fig, ax = plt.subplots(figsize=(11, 6.4))
    ax.set_xlim(-4.2, RECORD_BYTES + 0.2)
    ax.axis("off")
    ax.set_title("CompressedNode: 80 bytes, read as five 16-byte loads", fontsize=11,
                 fontweight="bold", loc="left")
    for byte in range(RECORD_BYTES):
        ax.text(byte + 0.5, -0.25, str(byte), ha="center", fontsize=7.5, color=GREY)
    for record in range(records):
        first = record * RECORD_BYTES
        ax.text(-0.15, record * 1.2 + 0.5, f"record {record}, bytes {first}-"
                f"{first + RECORD_BYTES - 1}", ha="right", va="center", fontsize=8.5,
                color=GREY)
    # A field never straddles two records: each record is one load, and the struct's order
    # keeps every field inside its 16 bytes.
    for first, size, label, colour in FIELDS:
        record, column = divmod(first, RECORD_BYTES)
        assert column + size <= RECORD_BYTES, label
        y = record * 1.2
        ax.add_patch(Rectangle((column, y), size, 1.0, facecolor=colour, edgecolor="#333333",
                               linewidth=0.8))
        ax.text(column + size / 2, y + 0.5, label, ha="center", va="center",
                fontsize=9 if size > 1 else 7)
    y = records * 1.2 + 0.4
    for name, text in NOTES:
        ax.text(-4.0, y, name + ":", fontsize=8.5, fontweight="bold", color=GREY, va="top")
        ax.text(-1.6, y, text, fontsize=8.5, color=GREY, va="top", linespacing=1.35)
        y += 0.55 * (text.count("\n") + 1) + 0.1
    ax.set_ylim(y - 0.3, -0.6)  # byte 0 at the top left, as the struct reads
    save(fig, out / "09_compressed_node.svg")


# --- The collapse: a binary subtree cut into at most eight pieces, which become one wide node's
# children. The tree is small and made up for the picture; the cut is the greedy collapse of
# chapters/09_wide_bvh/collapse.cpp (greedy_children): open the piece with the largest box until
# there are eight pieces or only leaves are left.

# name: (half area of its box, triangles, children); a leaf has no children.
COLLAPSE_TREE = {
    "A": (100, 24, ("B", "C")),
    "B": (64, 14, ("D", "E")), "C": (50, 10, ("F", "G")),
    "D": (40, 8, ("H", "I")), "E": (20, 6, ("J", "K")),
    "F": (34, 6, ("L", "M")), "G": (18, 4, ("N", "O")),
    "H": (25, 4, ("P", "Q")), "I": (16, 4, ("R", "S")), "J": (9, 3, ()), "K": (8, 3, ()),
    "L": (19, 3, ("T", "U")), "M": (12, 3, ()), "N": (8, 2, ()), "O": (7, 2, ()),
    "P": (10, 2, ()), "Q": (12, 2, ()), "R": (8, 2, ()), "S": (7, 2, ()), "T": (9, 2, ()),
    "U": (8, 1, ()),
}
PIECE = "#cfe2f3"
OPENED = "#eeeeee"


def greedy_cut(tree, root, width=8):
    """The pieces of the greedy collapse of `root`, and the nodes it opened (in order)."""
    pieces, opened = list(tree[root][2]), [root]
    while len(pieces) < width:
        open_able = [p for p in pieces if tree[p][2]]
        if not open_able:
            break
        largest = max(open_able, key=lambda p: tree[p][0])
        at = pieces.index(largest)
        pieces[at:at + 1] = tree[largest][2]  # its two children take its place
        opened.append(largest)
    return pieces, opened


def tree_positions(tree, root):
    """x by in-order leaf count, y by depth: a readable layout of the binary tree."""
    positions, next_x = {}, [0]

    def place(name, depth):
        children = tree[name][2]
        if not children:
            positions[name] = (next_x[0], -depth)
            next_x[0] += 1
            return
        for child in children:
            place(child, depth + 1)
        xs = [positions[c][0] for c in children]
        positions[name] = (sum(xs) / len(xs), -depth)

    place(root, 0)
    return positions


def collapse(out):
    pieces, opened = greedy_cut(COLLAPSE_TREE, "A")
    positions = tree_positions(COLLAPSE_TREE, "A")
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.6),
                                      gridspec_kw={"width_ratios": [1.35, 1]})
    for ax in (left, right):
        ax.axis("off")
    left.set_title("The binary subtree: a cut of at most 8 pieces", fontsize=10.5, loc="left")
    below_cut = set()

    def mark_below(name):
        for child in COLLAPSE_TREE[name][2]:
            below_cut.add(child)
            mark_below(child)

    for piece in pieces:
        mark_below(piece)
    for name, (_, _, children) in COLLAPSE_TREE.items():
        for child in children:
            (x0, y0), (x1, y1) = positions[name], positions[child]
            faint = child in below_cut
            left.plot([x0, x1], [y0, y1], color="#bbbbbb" if faint else "#444444",
                      linewidth=0.8, zorder=1)
    for name, (area, triangles, children) in COLLAPSE_TREE.items():
        x, y = positions[name]
        if name in pieces:
            colour, edge = PIECE, "#1f4e79"
        elif name in opened:
            colour, edge = OPENED, "#444444"
        else:
            colour, edge = "white", "#bbbbbb"
        left.add_patch(Rectangle((x - 0.38, y - 0.22), 0.76, 0.44, facecolor=colour,
                                 edgecolor=edge, linewidth=1.2 if name in pieces else 0.8,
                                 zorder=2))
        left.text(x, y + 0.04, name, ha="center", va="center", fontsize=9, zorder=3,
                  color="black" if name not in below_cut else "#999999")
        left.text(x, y - 0.36, f"A={area}", ha="center", va="top", fontsize=6.5, color=GREY)
    order = ", ".join(opened[1:])
    left.text(-0.4, -5.0, f"grey: opened, largest box first (A, then {order});\n"
              "blue: the 8 pieces the cut keeps; faint: below the cut, left to the\n"
              "pieces' own wide nodes", fontsize=8, color=GREY, va="top")
    left.set_xlim(-0.6, max(x for x, _ in positions.values()) + 0.6)
    left.set_ylim(-5.7, 0.6)

    right.set_title("One wide node: the pieces become its children", fontsize=10.5, loc="left")
    right.set_xlim(0, 8)
    right.set_ylim(-3.2, 1.4)
    right.add_patch(Rectangle((0.1, 0.3), 7.8, 0.8, facecolor=OPENED, edgecolor="#444444"))
    right.text(4.0, 0.7, "wide node made of A (A's box, 8 child boxes)", ha="center",
               va="center", fontsize=9)
    for c, piece in enumerate(pieces):
        area, triangles, children = COLLAPSE_TREE[piece]
        x = c + 0.1
        right.plot([4.0, x + 0.45], [0.3, -0.6], color="#444444", linewidth=0.7)
        right.add_patch(Rectangle((x, -1.4), 0.8, 0.8, facecolor=PIECE, edgecolor="#1f4e79"))
        right.text(x + 0.4, -1.0, piece, ha="center", va="center", fontsize=9)
        kind = "wide\nnode" if children else f"leaf\n{triangles} tri"
        right.text(x + 0.4, -1.55, kind, ha="center", va="top", fontsize=7, color=GREY)
    right.text(0.1, -2.45, "A piece that is a binary leaf (at most 3 triangles) stays a leaf;\n"
               "any other becomes a wide node of its own, collapsed the same way.\n"
               "The SAH collapse weighs every cut, and leaf against node, by\n"
               "dynamic programming instead.", fontsize=8, color=GREY, va="top")
    save(fig, out / "09_collapse.svg")


# --- Quantised child boxes, in 2D. The grid of one node along each axis (collapse.h, AxisGrid):
# origin = the node box's lo, step = the smallest power of two for which the last plane reaches
# the node box's hi; each child plane is the nearest grid plane on the outer side (quantise_lo,
# quantise_hi). The real grid has 256 planes (q = 0..255); the picture draws 16 (q = 0..15) so
# that the planes can be seen.

GRID_PLANES = 16
PARENT_BOX = ((1.0, 0.5), (12.3, 4.1))  # (lo, hi) in x and y
CHILD_BOX = ((3.3, 1.15), (7.6, 2.6))


def grid_step(lo, hi, planes=GRID_PLANES):
    step = 2.0 ** -10
    while lo + (planes - 1) * step < hi:
        step *= 2.0
    return step


def quantise(child_lo, child_hi, origin, step, planes=GRID_PLANES):
    q_lo = max(q for q in range(planes) if origin + q * step <= child_lo)
    q_hi = min(q for q in range(planes) if origin + q * step >= child_hi)
    return q_lo, q_hi


def quantised_box(out):
    (plx, ply), (phx, phy) = PARENT_BOX
    (clx, cly), (chx, chy) = CHILD_BOX
    step_x, step_y = grid_step(plx, phx), grid_step(ply, phy)
    qx, qy = quantise(clx, chx, plx, step_x), quantise(cly, chy, ply, step_y)
    fig, ax = plt.subplots(figsize=(11, 5.0))
    ax.axis("off")
    ax.set_title(f"A child box on its parent's grid ({GRID_PLANES} planes per axis drawn; the "
                 "node stores 256)", fontsize=10.5, loc="left")
    top_x, top_y = plx + (GRID_PLANES - 1) * step_x, ply + (GRID_PLANES - 1) * step_y
    for q in range(GRID_PLANES):
        x = plx + q * step_x
        ax.plot([x, x], [ply, top_y], color="#cccccc", linewidth=0.6, zorder=1)
        ax.text(x, ply - 0.12, str(q), ha="center", va="top", fontsize=6.5, color=GREY)
    for q in range(GRID_PLANES):
        y = ply + q * step_y
        ax.plot([plx, top_x], [y, y], color="#cccccc", linewidth=0.6, zorder=1)
        ax.text(plx - 0.12, y, str(q), ha="right", va="center", fontsize=6.5, color=GREY)
    ax.add_patch(Rectangle((plx, ply), phx - plx, phy - ply, fill=False, edgecolor="#333333",
                           linewidth=1.4, zorder=3))
    ax.text(phx - 0.05, phy + 0.08, "parent box", ha="right", va="bottom", fontsize=8.5)
    ax.add_patch(Rectangle((plx + qx[0] * step_x, ply + qy[0] * step_y),
                           (qx[1] - qx[0]) * step_x, (qy[1] - qy[0]) * step_y,
                           facecolor="#f4cccc", edgecolor="#cc0000", linewidth=1.3,
                           linestyle="--", zorder=2))
    ax.add_patch(Rectangle((clx, cly), chx - clx, chy - cly, facecolor="#cfe2f3",
                           edgecolor="#1f4e79", linewidth=1.3, zorder=4))
    ax.text((clx + chx) / 2, (cly + chy) / 2, "child's exact box", ha="center", va="center",
            fontsize=8.5, zorder=5)
    ax.text(plx + qx[1] * step_x + 0.1, ply + qy[1] * step_y + 0.05,
            f"stored: q_lo = ({qx[0]}, {qy[0]}), q_hi = ({qx[1]}, {qy[1]})", fontsize=8.5,
            color="#cc0000", va="bottom")
    ax.plot(plx, ply, "o", color="black", markersize=4, zorder=6)
    ax.text(plx + 0.1, ply + 0.08, "origin", fontsize=8, zorder=6)
    ax.text(top_x + 0.3, ply + (top_y - ply) / 2,
            f"step x = {step_x:g}, step y = {step_y:g}:\npowers of two, the smallest\n"
            "for which the last plane\nreaches the parent's hi\n(the grid may overshoot it).\n\n"
            "lo rounds down, hi rounds up:\nthe stored box always holds\nthe exact one.",
            fontsize=8.5, color=GREY, va="center")
    ax.set_xlim(plx - 0.6, top_x + 5.2)
    ax.set_ylim(ply - 0.6, top_y + 0.5)
    save(fig, out / "09_quantised_box.svg")


# --- Octant order, in 2D: four quadrants stand for the eight octants. assign_slots
# (octant_slots.h) gives each child the slot whose diagonal it lies furthest back along, cheapest
# pair first; a ray of octant o then visits the slots o, o ^ 1, o ^ 2, o ^ 3 (the traversal's
# highest bit of 24 + (s ^ octant_inverse)).

OCTANT_CHILDREN = [((0.2, 0.2), (1.6, 1.5)), ((2.4, 0.3), (3.8, 1.4)),
                   ((0.3, 2.2), (1.5, 3.7)), ((2.1, 2.0), (3.7, 3.8))]
OCTANT_NODE = ((0.0, 0.0), (4.0, 4.0))


def assign_slots_2d(node, boxes):
    """assign_slots of octant_slots.h with two axes: slot bit 0 is x negative, bit 1 y."""
    (nlx, nly), (nhx, nhy) = node
    offsets = [(lx + hx - nlx - nhx, ly + hy - nly - nhy) for (lx, ly), (hx, hy) in boxes]
    slot_of, children_left, slots_free = [-1] * len(boxes), set(range(len(boxes))), set(range(4))
    while children_left:
        best = None
        for c in sorted(children_left):
            for s in range(4):
                if s not in slots_free:
                    continue
                cost = (-offsets[c][0] if s & 1 else offsets[c][0]) + \
                       (-offsets[c][1] if s & 2 else offsets[c][1])
                if best is None or cost < best[0]:
                    best = (cost, c, s)
        _, c, s = best
        slot_of[c] = s
        children_left.discard(c)
        slots_free.discard(s)
    return slot_of


def octant_order(out):
    slot_of = assign_slots_2d(OCTANT_NODE, OCTANT_CHILDREN)
    rays = [(0, (1.0, 0.55), "+x, +y"), (1, (-1.0, 0.6), "-x, +y"), (3, (-0.7, -1.0), "-x, -y")]
    fig, axes = plt.subplots(1, len(rays), figsize=(11, 4.2))
    for ax, (octant, direction, signs) in zip(axes, rays):
        ax.set_aspect("equal")
        ax.axis("off")
        ax.set_title(f"ray of octant {octant} ({signs})", fontsize=10)
        (nlx, nly), (nhx, nhy) = OCTANT_NODE
        ax.add_patch(Rectangle((nlx, nly), nhx - nlx, nhy - nly, fill=False,
                               edgecolor="#333333"))
        visit = [octant ^ k for k in range(4)]  # slots in visiting order
        for c, ((lx, ly), (hx, hy)) in enumerate(OCTANT_CHILDREN):
            rank = visit.index(slot_of[c]) + 1
            shade = ["#1f4e79", "#4a7fb0", "#8fb3d6", "#cfe2f3"][rank - 1]
            ax.add_patch(Rectangle((lx, ly), hx - lx, hy - ly, facecolor=shade,
                                   edgecolor="#333333", linewidth=0.8))
            ax.text((lx + hx) / 2, (ly + hy) / 2 + 0.15, str(rank), ha="center", va="center",
                    fontsize=14, fontweight="bold", color="white" if rank <= 2 else "black")
            ax.text((lx + hx) / 2, (ly + hy) / 2 - 0.35, f"slot {slot_of[c]}", ha="center",
                    va="center", fontsize=7.5, color="white" if rank <= 2 else "black")
        dx, dy = direction
        start = (2.0 - 2.6 * dx, 2.0 - 2.6 * dy)
        ax.annotate("", xy=(start[0] + 1.1 * dx, start[1] + 1.1 * dy), xytext=start,
                    arrowprops={"arrowstyle": "->", "color": "#cc0000", "linewidth": 1.6})
        ax.text(2.0, -0.45, "visits slots " + ", ".join(str(s) for s in visit), ha="center",
                va="top", fontsize=8.5, color=GREY)
        ax.set_xlim(-1.2, 5.2)
        ax.set_ylim(-1.2, 5.2)
    fig.suptitle("Octant order in 2D (4 quadrants for 8 octants): slot bit 0 = x negative, "
                 "bit 1 = y negative; numbers: the visiting order", fontsize=9.5, color=GREY,
                 y=0.02)
    save(fig, out / "09_octant_order.svg")


# --- A warp's lanes over time, binary against wide: an illustration, not a measurement. Eight
# lanes stand for 32; each lane's ray needs a made-up number of dependent node reads in the
# binary tree, and about a third as many in the 8-wide tree (log8 n against log2 n levels). A
# warp issues until its slowest ray is done; a finished lane sits idle until then.

LANE_NODE_READS = [27, 9, 41, 15, 22, 33, 12, 19]


def warp_lanes(out):
    wide_reads = [-(-reads // 3) for reads in LANE_NODE_READS]  # a third, rounded up
    rows = [("binary tree: one 2-box test per read", LANE_NODE_READS, 1.0),
            ("8-wide tree: one 8-box test per read (more arithmetic per step)", wide_reads, 2.2)]
    fig, axes = plt.subplots(len(rows), 1, figsize=(10, 5.4), sharex=True)
    longest = max(LANE_NODE_READS)
    for ax, (title, reads, read_cost) in zip(axes, rows):
        steps = max(reads)
        for lane, count in enumerate(reads):
            y = len(reads) - 1 - lane
            ax.add_patch(Rectangle((0, y + 0.1), count * read_cost, 0.8, facecolor="#cfe2f3",
                                   edgecolor="#1f4e79", linewidth=0.6))
            ax.add_patch(Rectangle((count * read_cost, y + 0.1), (steps - count) * read_cost,
                                   0.8, facecolor="#eeeeee", edgecolor="#bbbbbb",
                                   linewidth=0.6, hatch="///"))
            ax.text(-0.5, y + 0.5, f"lane {lane}", ha="right", va="center", fontsize=7.5,
                    color=GREY)
            ax.text(count * read_cost - 0.3, y + 0.5, str(count), ha="right", va="center",
                    fontsize=7)
        busy = sum(reads) / (steps * len(reads))
        ax.set_title(f"{title}: the warp runs {steps} reads; lanes busy {busy:.0%} of them",
                     fontsize=9.5, loc="left")
        ax.set_ylim(0, len(reads))
        ax.set_yticks([])
        for side in ("top", "right", "left"):
            ax.spines[side].set_visible(False)
    axes[-1].set_xlim(-4, longest * 1.0 + 2)
    axes[-1].set_xlabel("time (illustration: a wide read drawn as 2.2 binary reads; made-up "
                        "ray lengths, 8 lanes for 32)", fontsize=8.5, color=GREY)
    axes[-1].set_xticks([])
    fig.legend(handles=[Rectangle((0, 0), 1, 1, facecolor="#cfe2f3", edgecolor="#1f4e79"),
                        Rectangle((0, 0), 1, 1, facecolor="#eeeeee", edgecolor="#bbbbbb",
                                  hatch="///")],
               labels=["lane busy: its ray reads a node", "lane idle: its ray is done, the "
                       "warp is not"], loc="lower center", ncol=2, fontsize=8, frameon=False)
    fig.tight_layout(rect=(0, 0.07, 1, 1))
    save(fig, out / "09_warp_lanes.svg")


# --- The three ways to keep a warp busy, as measured on the H200
# (book/data/09_benchmark_h200.json): each variant's rays per second over wide4 packed's, for
# every scene and ray type.

SCENES = ["stanford-bunny", "armadillo-100k", "stanford-dragon", "conference",
          "sponza-dabrovic"]
SHORT_NAMES = {"stanford-bunny": "bunny", "armadillo-100k": "armadillo",
               "stanford-dragon": "dragon", "conference": "conference",
               "sponza-dabrovic": "Sponza"}
RAY_TYPES = ["primary", "ao", "diffuse"]
VARIANTS = [("shared stack", "#f9cb9c"), ("persistent", "#6fa8dc"), ("sorted rays", "#93c47d")]


def warp_variants(out, data_path):
    rows = json.loads(Path(data_path).read_text())["rows"]
    speed = {row["variant"]: row["throughput"] for row in rows}
    fig, ax = plt.subplots(figsize=(11, 4.2))
    labels, x = [], 0
    for scene in SCENES:
        for rays in RAY_TYPES:
            base = speed[f"{scene}, {rays}, wide4 packed"]
            for k, (variant, colour) in enumerate(VARIANTS):
                ratio = speed[f"{scene}, {rays}, wide4 packed, {variant}"] / base
                ax.bar(x + (k - 1) * 0.27, ratio - 1.0, width=0.25, bottom=1.0, color=colour,
                       edgecolor="#333333", linewidth=0.4,
                       label=variant if x == 0 else None)
            labels.append(f"{SHORT_NAMES[scene]}\n{rays}")
            x += 1
        if scene != SCENES[-1]:
            ax.axvline(x - 0.5, color="#cccccc", linewidth=0.6)
    ax.axhline(1.0, color="black", linewidth=0.8)
    ax.set_xticks(range(len(labels)))
    ax.set_xticklabels(labels, fontsize=7)
    ax.set_ylabel("Mrays/s over wide4 packed's", fontsize=9)
    ax.set_ylim(0.45, 1.12)
    ax.set_title("Three ways to keep a warp busy, on an H200 (1920x1080; the sort's time "
                 "counted): above 1 is faster", fontsize=10, loc="left")
    ax.legend(fontsize=8.5, loc="lower right", frameon=False)
    for side in ("top", "right"):
        ax.spines[side].set_visible(False)
    save(fig, out / "09_warp_variants.svg")


def main():
    out = Path(sys.argv[1] if len(sys.argv) > 1 else "book/images")
    data = Path(sys.argv[2] if len(sys.argv) > 2 else "book/data")
    plt.rcParams.update({"svg.hashsalt": "rt-course-ch09", "font.family": "DejaVu Sans"})
    compressed_node(out)
    collapse(out)
    quantised_box(out)
    octant_order(out)
    warp_lanes(out)
    warp_variants(out, data / "09_benchmark_h200.json")


if __name__ == "__main__":
    main()
