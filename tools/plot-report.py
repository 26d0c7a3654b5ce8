#!/usr/bin/env python3
"""Draws a chapter's plot (SVG, with matplotlib) from the JSON its report writes.

  tools/plot-report.py --metric NAME [--per RAYS_METRIC] [--rows PREFIX]... [--missing VALUE]
                       [--xlabel TEXT] [--ylabel TEXT] --title TEXT --out FILE.svg REPORT.json

One point per report row (only rows whose variant starts with one of the PREFIXes, when
given): x is the row's ms/frame, y its metric NAME (divided by the metric RAYS_METRIC and
multiplied by a million with --per), both on log scales. A row without the metric is left out,
or drawn at VALUE with --missing. A zero is drawn on the bottom edge, labelled 0. GPU rows are
blue, CPU rows red. The SVG carries no date and fixed ids, so the same data gives the same file.
"""
import argparse
import json
import math
import sys

import matplotlib

matplotlib.use("svg")
import matplotlib.pyplot as plt  # noqa: E402  (after the backend is chosen)
import matplotlib.ticker  # noqa: E402

COLOURS = {"gpu": "#2a7ab0", "cpu": "#c0392b"}


def selected_points(report, args):
    points = []
    for row in report["rows"]:
        metrics = row.get("metrics", {})
        prefix = next((p for p in args.rows if row["variant"].startswith(p)), None)
        if args.rows and prefix is None:
            continue
        if args.metric in metrics:
            value = metrics[args.metric]
        elif args.missing is not None:
            value = args.missing
        else:
            continue
        if args.per:
            value = value / metrics[args.per] * 1e6
        # A prefix that ends in a comma names a group ("leaks,"): the label is the rest.
        label = row["variant"]
        if prefix and prefix.rstrip().endswith(","):
            label = label[len(prefix):].strip(", ")
        points.append((row["ms_per_frame"], value, label, row["backend"]))
    return points


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--metric", required=True)
    parser.add_argument("--per")
    parser.add_argument("--rows", action="append", default=[])
    parser.add_argument("--missing", type=float)
    parser.add_argument("--title", required=True)
    parser.add_argument("--ylabel", default=None)
    parser.add_argument("--xlabel", default="ms per frame")
    parser.add_argument("--out", required=True)
    parser.add_argument("report")
    args = parser.parse_args()

    with open(args.report, encoding="utf-8") as f:
        report = json.load(f)
    points = selected_points(report, args)
    if not points:
        sys.exit(f"plot-report: no row of {args.report} has the metric {args.metric}")

    nonzero = [p[1] for p in points if p[1] > 0] or [1.0]
    floor = 10 ** (math.floor(math.log10(min(nonzero))) - 1)  # where a zero is drawn

    plt.rcParams.update({"svg.hashsalt": "rt-course", "font.size": 10})
    fig, ax = plt.subplots(figsize=(9.5, 4.4))
    fig.subplots_adjust(left=0.09, right=0.63, top=0.9, bottom=0.13)
    # The labels stand in a column right of the plot, top to bottom in the points' order, each
    # joined to its point by a faint line: they never overlap, however close the points are.
    order = sorted(range(len(points)), key=lambda i: (-points[i][1], points[i][0]))
    step = min(0.09, 1.0 / len(points))
    for rank, i in enumerate(order):
        x, y, label, backend = points[i]
        colour = COLOURS.get(backend, "#555555")
        y = max(y, floor)
        ax.scatter([x], [y], s=36, color=colour, zorder=3)
        ax.annotate(f"{label} ({backend})", xy=(x, y), xycoords="data",
                    xytext=(1.03, 1.0 - step * (rank + 0.5)), textcoords="axes fraction",
                    fontsize=8, color=colour, va="center", annotation_clip=False,
                    arrowprops={"arrowstyle": "-", "color": colour, "alpha": 0.35,
                                "linewidth": 0.8, "shrinkA": 0, "shrinkB": 3})
    ax.set_xscale("log")
    ax.set_yscale("log")
    has_zero = any(p[1] <= 0 for p in points)
    ax.set_ylim(floor / 2 if has_zero else min(nonzero) / 3, max(p[1] for p in points) * 3)
    if has_zero:
        default = ax.yaxis.get_major_formatter()
        ax.yaxis.set_major_formatter(matplotlib.ticker.FuncFormatter(
            lambda v, pos: "0" if math.isclose(v, floor) else default(v, pos)))
    ax.set_xlabel(f"{args.xlabel} (log)")
    ax.set_ylabel(f"{args.ylabel or args.metric} (log)")
    ax.set_title(args.title, fontsize=11, loc="left")
    ax.grid(True, which="major", color="#dddddd", linewidth=0.6)
    ax.margins(x=0.15)
    fig.savefig(args.out, format="svg", metadata={"Date": None})


if __name__ == "__main__":
    main()
