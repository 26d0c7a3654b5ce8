#!/usr/bin/env python3
"""The closing chapter's diagrams (book/images/closing_*.svg): where a ray's time goes when the
traversal runs as instructions on the SM (this course's tracers, and OptiX on a GPU without RT
cores) and when an RT core takes it over (a schematic, with no durations); and chapter 09's
4-wide packed tree against OptiX 9.0 on the H200, per scene and ray type, read from
book/data/09_benchmark_h200.json and book/data/anchors.json.

  tools/diagrams/closing.py [OUT_DIR]     (default: book/images)
"""
import json
import sys
from pathlib import Path

import matplotlib

matplotlib.use("svg")
matplotlib.rcParams["svg.hashsalt"] = "rt-course-closing"  # the same file on every run
matplotlib.rcParams["font.family"] = "DejaVu Sans"
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import FancyBboxPatch  # noqa: E402

BLUE, GREY, RED, GOLD, GREEN = "#2a7ab0", "#555555", "#c0392b", "#d4a017", "#2e8b57"
IDLE = "#e4e4e4"

SCENES = ["stanford-bunny", "armadillo-100k", "stanford-dragon", "conference", "sponza-dabrovic"]
RAY_TYPES = ["primary", "ao", "diffuse"]
TREE = "wide4 packed"


def save(fig, path):
    fig.savefig(path, format="svg", metadata={"Date": None}, bbox_inches="tight")
    plt.close(fig)


# ------------------------------------------------------------------------------------------
# Where a ray's time goes: software traversal against an RT core.

def block(ax, x, y, width, label, colour, height=0.62, text_colour="white"):
    ax.add_patch(FancyBboxPatch((x, y - height / 2), width, height,
                                boxstyle="round,pad=0,rounding_size=0.08", facecolor=colour,
                                edgecolor="white", linewidth=1.2))
    if label:
        ax.text(x + width / 2, y, label, ha="center", va="center", fontsize=8,
                color=text_colour)


def traversal_timelines(out):
    """Two rows per design: what the SM's lanes do, and what the RT core does. The widths are
    drawn, not measured: the picture shows which unit runs which step, not how long it takes."""
    fig, ax = plt.subplots(figsize=(11, 5.2))
    ax.set_xlim(-3.2, 14.2)
    ax.set_ylim(-0.2, 6.4)
    ax.axis("off")

    # Software traversal: every step is an instruction on the SM.
    ax.text(-3.1, 5.85, "Software traversal (this course; OptiX on an H200)", fontsize=11,
            weight="bold", color=GREY, va="center")
    ax.text(-3.1, 5.0, "SM lanes", fontsize=9.5, color=GREY, va="center")
    x = 0.0
    block(ax, x, 5.0, 1.3, "make ray", GREEN)
    x += 1.3
    for step in range(2):
        block(ax, x, 5.0, 1.5, "read node", BLUE)
        block(ax, x + 1.5, 5.0, 1.5, "box tests", BLUE)
        block(ax, x + 3.0, 5.0, 0.8, "stack", GREY)
        x += 3.8
        if step == 0:
            block(ax, x, 5.0, 1.4, "triangles", RED)
            x += 1.4
    block(ax, x, 5.0, 1.4, "shade", GOLD, text_colour="black")
    ax.text(-3.1, 4.15, "no RT core", fontsize=9.5, color=GREY, va="center")
    ax.plot([0, x + 1.4], [4.15, 4.15], color=IDLE, linewidth=6, solid_capstyle="butt")
    ax.annotate("", xy=(x, 3.55), xytext=(1.3, 3.55),
                arrowprops=dict(arrowstyle="<->", color=GREY, linewidth=1.0))
    ax.text((1.3 + x) / 2, 3.3, "the loop of chapters 07-09: nodes, boxes, stack, triangles, "
            "all issued by the SM, lanes waiting on each other's nodes", ha="center",
            fontsize=8.5, color=GREY, va="center")

    # Hardware traversal: the SM hands the ray over and runs other warps meanwhile.
    ax.text(-3.1, 2.55, "Hardware traversal (RT cores: NVIDIA since Turing)", fontsize=11,
            weight="bold", color=GREY, va="center")
    ax.text(-3.1, 1.7, "SM lanes", fontsize=9.5, color=GREY, va="center")
    block(ax, 0.0, 1.7, 1.3, "make ray", GREEN)
    block(ax, 1.3, 1.7, 0.9, "trace", GREY)
    block(ax, 2.2, 1.7, 6.0, "other warps: shading, sampling, more rays", IDLE,
          text_colour=GREY)
    block(ax, 8.2, 1.7, 1.4, "shade", GOLD, text_colour="black")
    ax.text(-3.1, 0.85, "RT core", fontsize=9.5, color=GREY, va="center")
    block(ax, 2.2, 0.85, 4.6, "nodes, boxes, stack: fixed function", BLUE)
    block(ax, 6.8, 0.85, 1.4, "triangles", RED)
    ax.annotate("", xy=(2.2, 1.05), xytext=(2.2, 1.38),
                arrowprops=dict(arrowstyle="-|>", color=GREY, linewidth=1.0))
    ax.annotate("", xy=(8.2, 1.38), xytext=(8.2, 1.05),
                arrowprops=dict(arrowstyle="-|>", color=GREY, linewidth=1.0))
    ax.text(8.5, 0.95, "what stays on the SM: making rays,\nshading, sampling, and "
            "the build", fontsize=8.5, color=GREY, va="top")
    ax.text(14.1, -0.1, "a schematic: the widths are drawn, not measured", ha="right",
            fontsize=8, color=GREY, style="italic")
    save(fig, out / "closing_traversal_timelines.svg")


# ------------------------------------------------------------------------------------------
# Chapter 09's tree against OptiX on the same GPU.

def measured_speedups(data):
    anchors = json.loads((data / "anchors.json").read_text())
    optix = next(s for s in anchors["sets"]
                 if s["system"].startswith("OptiX") and s["device"] == "NVIDIA H200")
    report = json.loads((data / "09_benchmark_h200.json").read_text())
    ours = {}
    for row in report["rows"]:
        if row["backend"] == "cpu":
            continue
        scene, ray_type, tracer = [part.strip() for part in row["variant"].split(",", 2)]
        if tracer == TREE:
            ours[(scene, ray_type)] = row["throughput"]
    return {(scene, ray_type): ours[(scene, ray_type)] / optix["scenes"][scene][ray_type]
            for scene in SCENES for ray_type in RAY_TYPES}


def speedup_bars(out, data):
    ratios = measured_speedups(data)
    fig, ax = plt.subplots(figsize=(10, 4.6))
    width = 0.26
    colours = {"primary": GREEN, "ao": GOLD, "diffuse": BLUE}
    names = {"primary": "camera rays", "ao": "ambient occlusion", "diffuse": "diffuse bounces"}
    for k, ray_type in enumerate(RAY_TYPES):
        xs = [i + (k - 1) * width for i in range(len(SCENES))]
        values = [ratios[(scene, ray_type)] for scene in SCENES]
        ax.bar(xs, values, width, color=colours[ray_type], label=names[ray_type])
        for x, value in zip(xs, values):
            ax.text(x, value + 0.03, f"{value:.2f}", ha="center", va="bottom", fontsize=7.5)
    ax.axhline(1.0, color=RED, linewidth=1.2, linestyle="--", label="OptiX 9.0")
    ax.set_xticks(range(len(SCENES)))
    ax.set_xticklabels(["bunny", "armadillo", "dragon", "conference", "Sponza"])
    ax.set_ylabel("rays per second, as a multiple of OptiX's")
    ax.set_ylim(0, 3.0)
    ax.set_title("Chapter 09's 4-wide packed tree against OptiX 9.0, both in software "
                 "(H200, 1920x1080)", fontsize=10.5)
    ax.legend(frameon=False, fontsize=9, loc="upper right", ncol=4)
    for side in ("top", "right"):
        ax.spines[side].set_visible(False)
    save(fig, out / "closing_wide4_against_optix.svg")


def main():
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path("book/images")
    data = Path(__file__).resolve().parents[2] / "book" / "data"
    out.mkdir(parents=True, exist_ok=True)
    traversal_timelines(out)
    speedup_bars(out, data)


if __name__ == "__main__":
    main()
