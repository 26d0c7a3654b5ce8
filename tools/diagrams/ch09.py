#!/usr/bin/env python3
"""Chapter 09's diagram (book/images/09_compressed_node.svg): the compressed wide node of
chapters/09_wide_bvh/wide_bvh.h (CompressedNode), 80 bytes read as five 16-byte records, byte by
byte, with what each field means.

  tools/diagrams/ch09.py [OUT_DIR]     (default: book/images)
"""
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


def main():
    out = Path(sys.argv[1] if len(sys.argv) > 1 else "book/images")
    plt.rcParams.update({"svg.hashsalt": "rt-course-ch09", "font.family": "DejaVu Sans"})
    compressed_node(out)


if __name__ == "__main__":
    main()
