#!/usr/bin/env python3
"""Summarises the CSV of tools/profile-paths.sh: one line per memory path and ray type.

Chapter 08's benchmark launches, per ray type, chapter 07's kernel (global) first and then
each path in turn (and, for primary rays, the two camera kernels), so consecutive launches of
one kernel are one measurement, and a new run of the global kernel starts the next ray type.
"""
import csv
import statistics
import sys

SHORT = {"gpu__time_duration.sum": "time", "l1tex__t_sector_hit_rate.pct": "L1 hit %",
         "lts__t_sector_hit_rate.pct": "L2 hit %",
         "l1tex__t_requests_pipe_lsu_mem_global_op_ld.sum": "LSU load requests",
         "l1tex__t_requests_pipe_tex_mem_texture.sum": "TEX requests",
         "dram__bytes_read.sum": "DRAM read", "smsp__inst_executed.sum": "instructions",
         "sm__warps_active.avg.pct_of_peak_sustained_active": "occupancy %"}
PATHS = [("TextureRecords", "texture"), ("ReadOnlyRecords", "float4_ldg"),
         ("GlobalRecords", "float4"), ("ReadOnlyBvh", "ldg"), ("BvhView", "global")]
TYPES = ["primary", "ao", "diffuse"]


def label(kernel):
    if "camera_trace" in kernel:
        return "camera in kernel, " + ("parameters" if "parameters" in kernel else "__constant__")
    return next((name for key, name in PATHS if key in kernel), kernel[:40])


def number(text):
    return float(text.replace(",", "")) if text not in ("", "n/a") else float("nan")


def main():
    lines = [l for l in open(sys.argv[1]) if l.startswith('"')]
    rows = list(csv.DictReader(lines))
    units = rows[0]
    rows = [r for r in rows[1:] if r.get("Kernel Name")]
    metrics = [m for m in SHORT if m in units]
    runs = []  # (label, [rows])
    for r in rows:
        name = label(r["Kernel Name"])
        if runs and runs[-1][0] == name:
            runs[-1][1].append(r)
        else:
            runs.append((name, [r]))
    header = ["ray type", "path"] + [f"{SHORT[m]} ({units[m]})" if units[m] else SHORT[m]
                                     for m in metrics]
    print("| " + " | ".join(header) + " |")
    print("|" + "---|" * len(header))
    type_index = -1
    for name, group in runs:
        if name == "global":
            type_index += 1
        cells = [statistics.mean(number(r[m]) for r in group) for m in metrics]
        ray_type = TYPES[type_index] if 0 <= type_index < len(TYPES) else "?"
        print("| " + " | ".join([ray_type, name] + [f"{c:,.4g}" for c in cells]) + " |")


if __name__ == "__main__":
    main()
