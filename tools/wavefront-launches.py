#!/usr/bin/env python3
"""Sums Nsight Compute's per-launch kernel times of chapters 11-12's wavefront by bounce.

    ncu --csv --metrics gpu__time_duration.sum,launch__grid_size \\
        ch12_materials --backend gpu --headless --width 1920 --height 1080 --spp 1 \\
        --image-only --variant wavefront > launches.csv
    tools/wavefront-launches.py launches.csv OUT.csv "what was measured"

Each Extend (or Complete, the stragglers' launch) starts a bounce; a row gives the bounce's
launches, the most paths its launches covered (grid size x 256 threads) and each stage's
milliseconds. The profiler runs one kernel at a time, so the sums are kernel time, not the
frame's wall time. Prints the totals.
"""
import collections
import csv
import sys

STAGES = ["Generate", "Extend", "Shade", "Connect", "Complete", "Finish"]
THREADS_PER_BLOCK = 256  # for_each_index's blocks (common/include/rt/launch.h)


def launches(path):
    rows = [r for r in csv.reader(open(path)) if len(r) > 10]
    header, rows = rows[0], rows[1:]
    at = {name: header.index(name) for name in ("ID", "Kernel Name", "Metric Name", "Metric Value")}
    by_id = collections.OrderedDict()
    for r in rows:
        launch = by_id.setdefault(r[at["ID"]], {"kernel": r[at["Kernel Name"]]})
        launch[r[at["Metric Name"]]] = float(r[at["Metric Value"]].replace(",", ""))
    for launch in by_id.values():
        kernel = launch["kernel"]
        stage = kernel.split("for_each_index_kernel<")[-1].split("<")[0]
        yield (stage if stage in STAGES else "other", launch["gpu__time_duration.sum"] / 1e6,
               int(launch["launch__grid_size"]))


def main():
    source, destination, title = sys.argv[1:4]
    bounces = [dict(bounce=0, launches=0, paths=0, **{s: 0.0 for s in STAGES})]
    for stage, ms, grid in launches(source):
        if stage in ("Extend", "Complete"):
            bounces.append(dict(bounce=len(bounces), launches=0, paths=grid * THREADS_PER_BLOCK,
                                **{s: 0.0 for s in STAGES}))
        if stage in STAGES:
            bounces[-1][stage] += ms
            bounces[-1]["launches"] += 1
    with open(destination, "w") as out:
        out.write("# " + title + "\n")
        out.write("bounce,launches,paths_at_most," + ",".join(s.lower() + "_ms" for s in STAGES) + "\n")
        for b in bounces:
            out.write("%d,%d,%d," % (b["bounce"], b["launches"], b["paths"]) +
                      ",".join("%.4f" % b[s] for s in STAGES) + "\n")
    total = sum(sum(b[s] for s in STAGES) for b in bounces)
    print("%s: %d launches, %d bounces, %.2f ms of kernel time" %
          (destination, sum(b["launches"] for b in bounces), len(bounces) - 1, total))


if __name__ == "__main__":
    main()
