#!/usr/bin/env python3
"""Draws chapter 11's error against run time (SVG, with matplotlib) from its --convergence JSON.

  tools/plot-convergence.py [--metric rel_mse|rmse] [--time wall_ms|kernel_ms]
                            [--title TEXT] --out FILE.svg REPORT.json

One line per variant (the row's name before its ", N spp"), one point per sample count: x is
the time to reach it, y the error against the reference, both on log scales. The legend gives
each line's least-squares slope in log-log: an unbiased estimator's mean squared error falls
as 1 / time, a slope of -1 (-0.5 for the RMSE). The SVG carries no date and fixed ids, so the
same data gives the same file.
"""
import argparse
import json
import math
import sys

import matplotlib

matplotlib.use("svg")
import matplotlib.pyplot as plt  # noqa: E402  (after the backend is chosen)

COLOURS = ["#c0392b", "#2a7ab0", "#27ae60", "#8e44ad", "#d68910", "#566573"]


def lines_of(report, metric, time):
    lines = {}
    for row in report["rows"]:
        metrics = row.get("metrics", {})
        if metric not in metrics or time not in metrics:
            continue
        variant = row["variant"].rsplit(",", 1)[0]
        lines.setdefault(variant, []).append((metrics[time] / 1000.0, metrics[metric]))
    return lines


def slope(points):
    """Least-squares slope of log(error) against log(time)."""
    usable = [(math.log(t), math.log(e)) for t, e in points if t > 0 and e > 0]
    if len(usable) < 2:
        return float("nan")
    mx = sum(x for x, _ in usable) / len(usable)
    my = sum(y for _, y in usable) / len(usable)
    sxx = sum((x - mx) ** 2 for x, _ in usable)
    return sum((x - mx) * (y - my) for x, y in usable) / sxx if sxx > 0 else float("nan")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("report")
    parser.add_argument("--metric", default="rel_mse", choices=["rel_mse", "rmse"])
    parser.add_argument("--time", default="wall_ms", choices=["wall_ms", "kernel_ms"])
    parser.add_argument("--title", default="Error against run time")
    parser.add_argument("--out", required=True)
    args = parser.parse_args()
    with open(args.report) as f:
        report = json.load(f)
    lines = lines_of(report, args.metric, args.time)
    if not lines:
        sys.exit(f"{args.report}: no rows with the metrics {args.metric} and {args.time}")

    plt.rcParams["svg.hashsalt"] = "ch11"  # fixed ids: the same data gives the same file
    figure, axes = plt.subplots(figsize=(6.4, 4.2))
    for k, (variant, points) in enumerate(sorted(lines.items())):
        points.sort()
        axes.plot([t for t, _ in points], [e for _, e in points], marker="o",
                  color=COLOURS[k % len(COLOURS)],
                  label=f"{variant} (slope {slope(points):.2f})")
    axes.set_xscale("log")
    axes.set_yscale("log")
    axes.set_xlabel("seconds" + (" (kernels)" if args.time == "kernel_ms" else ""))
    axes.set_ylabel("relative MSE" if args.metric == "rel_mse" else "RMSE")
    axes.set_title(args.title)
    axes.grid(True, which="both", linewidth=0.3)
    axes.legend(fontsize=8)
    figure.tight_layout()
    figure.savefig(args.out, metadata={"Date": None})
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
