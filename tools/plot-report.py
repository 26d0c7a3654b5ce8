#!/usr/bin/env python3
"""Draws a chapter's error-against-run-time plot (SVG) from the JSON its report writes.

  tools/plot-report.py --metric NAME [--per RAYS_METRIC] [--rows PREFIX] [--xlabel TEXT]
                       [--ylabel TEXT] --title TEXT --out FILE.svg REPORT.json

One point per report row (optionally only rows whose variant starts with PREFIX): x is the
row's ms/frame, y its metric NAME (divided by the metric RAYS_METRIC and multiplied by a
million with --per), both on log scales. A zero error is drawn on the bottom edge, labelled 0.
Only the standard library is used, so the plot can be redrawn anywhere.
"""
import argparse
import json
import math
import sys
from xml.sax.saxutils import escape

WIDTH, HEIGHT = 900, 420
LEFT, RIGHT, TOP, BOTTOM = 80, 340, 40, 60
COLOURS = {"gpu": "#2a7ab0", "cpu": "#c0392b"}


def decades(lo, hi):
    return range(math.floor(math.log10(lo)), math.ceil(math.log10(hi)) + 1)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--metric", required=True)
    parser.add_argument("--per")
    parser.add_argument("--rows", default="")
    parser.add_argument("--title", required=True)
    parser.add_argument("--ylabel", default=None)
    parser.add_argument("--xlabel", default="ms per frame")
    parser.add_argument("--out", required=True)
    parser.add_argument("report")
    args = parser.parse_args()

    with open(args.report, encoding="utf-8") as f:
        report = json.load(f)
    points = []
    for row in report["rows"]:
        metrics = row.get("metrics", {})
        if not row["variant"].startswith(args.rows) or args.metric not in metrics:
            continue
        value = metrics[args.metric]
        if args.per:
            value = value / metrics[args.per] * 1e6
        label = row["variant"][len(args.rows):].strip(", ")
        points.append((row["ms_per_frame"], value, label, row["backend"]))
    if not points:
        sys.exit(f"plot-report: no row of {args.report} has the metric {args.metric}")

    xs = [p[0] for p in points]
    nonzero = [p[1] for p in points if p[1] > 0] or [1.0]
    x_lo, x_hi = 10 ** math.floor(math.log10(min(xs))), 10 ** math.ceil(math.log10(max(xs)))
    y_hi = 10 ** math.ceil(math.log10(max(nonzero)))
    y_lo = 10 ** (math.floor(math.log10(min(nonzero))) - 1)
    if x_hi == x_lo:
        x_hi *= 10

    def sx(x):
        return LEFT + (math.log10(x) - math.log10(x_lo)) / (
            math.log10(x_hi) - math.log10(x_lo)) * (WIDTH - LEFT - RIGHT)

    def sy(y):
        y = max(y, y_lo)
        return HEIGHT - BOTTOM - (math.log10(y) - math.log10(y_lo)) / (
            math.log10(y_hi) - math.log10(y_lo)) * (HEIGHT - TOP - BOTTOM)

    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{WIDTH}" height="{HEIGHT}" '
           f'font-family="sans-serif" font-size="12">',
           f'<rect width="{WIDTH}" height="{HEIGHT}" fill="white"/>',
           f'<text x="{LEFT}" y="24" font-size="15">{escape(args.title)}</text>']
    for e in decades(x_lo, x_hi):
        x = sx(10 ** e)
        out.append(f'<line x1="{x:.1f}" y1="{TOP}" x2="{x:.1f}" y2="{HEIGHT - BOTTOM}" '
                   f'stroke="#ddd"/>')
        out.append(f'<text x="{x:.1f}" y="{HEIGHT - BOTTOM + 16}" text-anchor="middle">'
                   f'1e{e}</text>')
    for e in decades(y_lo, y_hi):
        y = sy(10 ** e)
        out.append(f'<line x1="{LEFT}" y1="{y:.1f}" x2="{WIDTH - RIGHT}" y2="{y:.1f}" '
                   f'stroke="#ddd"/>')
        text = "0" if e == math.log10(y_lo) else f"1e{e}"
        out.append(f'<text x="{LEFT - 6}" y="{y + 4:.1f}" text-anchor="end">{text}</text>')
    out.append(f'<text x="{(LEFT + WIDTH - RIGHT) / 2}" y="{HEIGHT - 16}" '
               f'text-anchor="middle">{escape(args.xlabel)} (log)</text>')
    ylabel = escape(args.ylabel or args.metric)
    out.append(f'<text transform="translate(18,{(TOP + HEIGHT - BOTTOM) / 2}) rotate(-90)" '
               f'text-anchor="middle">{ylabel} (log)</text>')
    for i, (x, y, label, backend) in enumerate(points):
        colour = COLOURS.get(backend, "#555")
        px, py = sx(x), sy(y)
        out.append(f'<circle cx="{px:.1f}" cy="{py:.1f}" r="5" fill="{colour}"/>')
        ly = TOP + 14 + 16 * i
        out.append(f'<line x1="{px:.1f}" y1="{py:.1f}" x2="{WIDTH - RIGHT + 8}" y2="{ly - 4}" '
                   f'stroke="{colour}" stroke-opacity="0.35"/>')
        out.append(f'<text x="{WIDTH - RIGHT + 12}" y="{ly}" fill="{colour}">'
                   f'{escape(label)} ({backend})</text>')
    out.append("</svg>")
    with open(args.out, "w", encoding="utf-8") as f:
        f.write("\n".join(out) + "\n")


if __name__ == "__main__":
    main()
