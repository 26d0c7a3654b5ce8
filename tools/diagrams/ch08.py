#!/usr/bin/env python3
"""Chapter 08's diagrams and plots (book/images/08_*.svg): the memory a Hopper multiprocessor
reads the tree through, the packed 16-byte records, each memory path's speed against chapter
07's plain loads, and the read-only promise's loss on the wide loads (float4_ldg against
float4, on the H100 and the H200), from the benchmarks' JSON in book/data.

  tools/diagrams/ch08.py [OUT_DIR]     (default: book/images)
"""
import json
import sys
from pathlib import Path

import matplotlib

matplotlib.use("svg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import FancyArrowPatch, Rectangle  # noqa: E402

BLUE, GREY, RED, GREEN, GOLD = "#2a7ab0", "#555555", "#c0392b", "#2e8b57", "#d4a017"
BOOK_DATA = Path(__file__).resolve().parents[2] / "book" / "data"
DATA = BOOK_DATA / "08_benchmark.json"
DATA_H200 = BOOK_DATA / "08_benchmark_h200.json"


def save(fig, path):
    fig.savefig(path, format="svg", metadata={"Date": None}, bbox_inches="tight")


def block(ax, x, y, w, h, title, body, colour, face):
    ax.add_patch(Rectangle((x, y), w, h, facecolor=face, edgecolor=colour, linewidth=1.2))
    ax.text(x + w / 2, y + h - 0.15, title, ha="center", va="top", fontsize=9,
            fontweight="bold", color=colour)
    if body:
        ax.text(x + w / 2, y + h - 0.5, body, ha="center", va="top", fontsize=7.5, color=GREY)


def arrow(ax, start, end, colour, text=None, side=0.1):
    ax.add_patch(FancyArrowPatch(start, end, arrowstyle="-|>", mutation_scale=11, color=colour,
                                 linewidth=1.1))
    if text:
        ax.text(start[0] + side, (start[1] + end[1]) / 2, text, fontsize=7.3, color=colour,
                va="center")


def hopper(out):
    fig, ax = plt.subplots(figsize=(11, 6.2))
    ax.set_xlim(0, 16)
    ax.set_ylim(0, 10)
    ax.axis("off")
    ax.add_patch(Rectangle((0.2, 3.6), 10.6, 6.2, facecolor="none", edgecolor=GREY,
                           linestyle="--"))
    ax.text(0.35, 9.65, "one streaming multiprocessor (SM); an H100 SXM has 132, the H200 as "
            "many", fontsize=8.5, color=GREY, va="top")
    block(ax, 0.6, 7.6, 4.2, 1.5, "registers", "65 536 × 32 bits per SM,\nshared by its resident "
          "threads", BLUE, "#eef5fb")
    block(ax, 5.6, 7.6, 4.8, 1.5, "load/store unit · texture unit",
          "LDG, LDG.CONSTANT (__ldg)   ·   TLD\n(tex1Dfetch)", BLUE, "#eef5fb")
    block(ax, 0.6, 4.0, 6.2, 2.7, "L1 data cache = texture cache = shared memory",
          "one 256 KB unit per SM: the read-only data\ncache of __ldg is this L1 too; so is the "
          "texture\ncache. Local memory (the traversal stack,\nspills) is cached here on its "
          "way to DRAM", GREEN, "#eef8f1")
    block(ax, 7.4, 4.0, 3.0, 2.7, "constant cache", "kernel parameters (bank 0)\nand "
          "__constant__ data:\nLDC, ULDC", GOLD, "#fbf3e0")
    arrow(ax, (7.4, 7.6), (4.5, 6.75), BLUE, "tree loads, all paths", -3.6)
    arrow(ax, (2.7, 7.6), (2.7, 6.75), GREY)
    block(ax, 0.6, 1.6, 9.8, 1.3, "L2 cache: 50 MB, shared by all SMs",
          "the tree of every benchmark scene (20-25 MB) stays here; L1 misses are served from it",
          GREEN, "#eef8f1")
    block(ax, 0.6, 0.1, 9.8, 1.1, "DRAM (HBM3 80 GB on the H100, HBM3e 141 GB on the H200)",
          "", GREY, "#f4f4f4")
    arrow(ax, (3.7, 4.0), (3.7, 2.95), GREEN)
    arrow(ax, (8.9, 4.0), (8.9, 2.95), GOLD)
    arrow(ax, (5.5, 1.6), (5.5, 1.25), GREY)
    ax.text(11.2, 9.0, "What the paths change", fontsize=9.5, fontweight="bold", color=GREY,
            va="top")
    ax.text(11.2, 8.5, "global: 16 four-byte LDG per node\n\nldg: the same, as LDG.CONSTANT:\n"
            "same L1, same pipeline\n\nfloat4: 4 sixteen-byte LDG.128\nper node: a quarter "
            "of the\nload instructions\n\ntexture: 4 TLD per node, through\nthe texture unit, "
            "into the same L1\n\n__constant__: the camera and the\ntree's pointers, read "
            "like kernel\nparameters", fontsize=8, color=GREY, va="top", linespacing=1.3)
    save(fig, out / "08_hopper_memory.svg")


def records(out):
    fig, ax = plt.subplots(figsize=(11, 4.0))
    ax.set_xlim(0, 17)
    ax.set_ylim(0, 6.3)
    ax.axis("off")
    node = [["box[0].lo.x", "lo.y", "lo.z", "box[0].hi.x"],
            ["box[0].hi.y", "hi.z", "box[1].lo.x", "lo.y"],
            ["box[1].lo.z", "box[1].hi.x", "hi.y", "hi.z"],
            ["first[0]", "first[1]", "count[0]", "count[1]"]]
    tri = [["v0.x", "v0.y", "v0.z", "triangle id"], ["v1.x", "v1.y", "v1.z", "0"],
           ["v2.x", "v2.y", "v2.z", "0"]]

    def rows(x0, title, grid, ints):
        ax.text(x0, 5.95, title, fontsize=9.5, fontweight="bold", color=BLUE)
        for r, row in enumerate(grid):
            y = 5.0 - r * 1.0
            ax.text(x0 - 0.15, y + 0.4, f"r{r}", ha="right", va="center", fontsize=8,
                    color=GREY)
            for c, field in enumerate(row):
                is_int = (r, c) in ints
                ax.add_patch(Rectangle((x0 + 1.6 * c, y), 1.6, 0.8,
                                       facecolor="#fbeeee" if is_int else "#eef5fb",
                                       edgecolor=RED if is_int else BLUE, linewidth=0.8))
                ax.text(x0 + 1.6 * c + 0.8, y + 0.4, field, ha="center", va="center",
                        fontsize=7.2)
            ax.text(x0 + 6.5, y + 0.4, "one 16-byte load", fontsize=7, color=GREEN,
                    va="center")

    rows(0.6, "node i: records 4i .. 4i+3 (64 bytes)", node, {(3, 0), (3, 1), (3, 2), (3, 3)})
    rows(9.4, "triangle k: records 3k .. 3k+2 (48 bytes)", tri, {(0, 3)})
    ax.text(0.6, 0.5, "blue: float lanes; red: int bits in a float lane, moved as bits "
            "(__float_as_int, memcpy), never as values: an id whose bits are a NaN comes back "
            "unchanged.\nThe node's bytes are chapter 07's exactly; the triangle's id, a "
            "separate array in chapter 07, rides in v0's spare lane.", fontsize=8, color=GREY)
    save(fig, out / "08_packed_records.svg")


def gpu_speeds(data):
    """Mrays/s of each (scene, ray type, path) row the GPU measured, the camera kernels left
    out (their variants name more than three things)."""
    with open(data, encoding="utf-8") as f:
        report = json.load(f)
    speed = {}
    for row in report["rows"]:
        parts = [p.strip() for p in row["variant"].split(",")]
        if row["backend"] != "gpu" or len(parts) != 3:
            continue
        scene, ray_type, path = parts
        speed[(scene, ray_type, path)] = row["metrics"]["mrays_per_s"]
    return speed


def paths_plot(out):
    speed = gpu_speeds(DATA)
    paths = ["ldg", "float4", "float4_ldg", "texture"]
    ray_types = ["primary", "ao", "diffuse"]
    scenes = sorted({k[0] for k in speed if k[2] == "global"})
    colours = {"ldg": GOLD, "float4": BLUE, "float4_ldg": RED, "texture": GREEN}
    fig, ax = plt.subplots(figsize=(10, 4.2))
    for t, ray_type in enumerate(ray_types):
        for p, path in enumerate(paths):
            x = t * 5 + p
            ratios = [speed[(s, ray_type, path)] / speed[(s, ray_type, "global")]
                      for s in scenes if (s, ray_type, path) in speed]
            ax.scatter([x] * len(ratios), ratios, color=colours[path], s=22, zorder=3,
                       label=path if t == 0 else None)
    ax.axhline(1.0, color=GREY, linewidth=0.8)
    ax.set_xticks([t * 5 + 1.5 for t in range(3)], ["primary rays", "ambient occlusion",
                                                     "diffuse rays"])
    ax.set_ylabel("Mrays/s relative to global")
    ax.set_title("Chapter 08: each memory path against plain loads, one point per scene "
                 "(H100, 1920x1080)", fontsize=10, loc="left")
    ax.grid(True, axis="y", color="#dddddd", linewidth=0.6)
    ax.legend(loc="upper left", fontsize=8, ncol=4)
    ax.set_ylim(0.9, 1.5)
    save(fig, out / "08_paths_vs_global.svg")


def read_only_plot(out):
    """The failure of a rule: __ldg added to the 16-byte loads (float4_ldg) against the same
    loads without it (float4), cell by cell, on both GPUs the benchmark ran on."""
    gpus = [("H100", DATA, "o", BLUE), ("H200", DATA_H200, "^", RED)]
    ray_types = [("primary", "primary rays"), ("ao", "ambient occlusion"),
                 ("diffuse", "diffuse rays")]
    fig, ax = plt.subplots(figsize=(10, 4.4))
    scenes = []
    for g, (name, data, marker, colour) in enumerate(gpus):
        speed = gpu_speeds(data)
        scenes = list(dict.fromkeys(k[0] for k in speed))  # in the benchmark's order
        slower = cells = 0
        for t, (ray_type, _) in enumerate(ray_types):
            for s, scene in enumerate(scenes):
                ratio = (speed[(scene, ray_type, "float4_ldg")] /
                         speed[(scene, ray_type, "float4")])
                slower += ratio < 1.0
                cells += 1
                ax.scatter(t * (len(scenes) + 1) + s, ratio, marker=marker, color=colour, s=30,
                           zorder=3, label=name if t == 0 and s == 0 else None)
        ax.text(0.99, 0.97 - 0.07 * g,
                f"{name}: float4_ldg slower in {slower} of {cells} cells", ha="right",
                va="top", transform=ax.transAxes, fontsize=8, color=colour)
    ax.axhspan(0.8, 1.0, color="#fbeeee", zorder=0)
    ax.axhline(1.0, color=GREY, linewidth=0.8)
    ticks = [t * (len(scenes) + 1) + s
             for t in range(len(ray_types)) for s in range(len(scenes))]
    ax.set_xticks(ticks, scenes * len(ray_types), rotation=35, ha="right", fontsize=7.5)
    for t, (_, label) in enumerate(ray_types):
        ax.text(t * (len(scenes) + 1) + (len(scenes) - 1) / 2, 1.125, label, ha="center",
                fontsize=9, color=GREY)
    ax.text(-0.4, 0.81, "below 1: the read-only promise made the wide loads slower", fontsize=8,
            color=RED)
    ax.set_ylabel("float4_ldg Mrays/s / float4 Mrays/s")
    ax.set_ylim(0.8, 1.22)
    ax.set_title("Chapter 08: __ldg on the 16-byte loads, against the same loads without it "
                 "(1920x1080)", fontsize=10, loc="left")
    ax.grid(True, axis="y", color="#dddddd", linewidth=0.6)
    ax.legend(loc="upper left", fontsize=8, ncol=2)
    save(fig, out / "08_read_only_loss.svg")


def main():
    out = Path(sys.argv[1] if len(sys.argv) > 1 else "book/images")
    plt.rcParams.update({"svg.hashsalt": "rt-course-ch08", "font.family": "DejaVu Sans"})
    hopper(out)
    records(out)
    paths_plot(out)
    read_only_plot(out)


if __name__ == "__main__":
    main()
