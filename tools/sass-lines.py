#!/usr/bin/env python3
"""Sums Nsight Compute's per-instruction counters of one kernel by source file and line.

A kernel built with -lineinfo carries, for each machine instruction, the source line it came
from (the innermost one where functions were inlined). nvdisasm prints it; Nsight Compute's
source page prints each instruction's counters by address. This joins the two:

    cuobjdump -xelf all ch12_materials            # one .cubin per CUDA file
    nvdisasm -g -c material_render.sm_90.cubin > dis.txt
    ncu --kernel-name-base demangled -k regex:Shade --launch-skip 1 -c 1 \\
        --section SourceCounters --section WarpStateStats -o shade ch12_materials ...
    ncu -i shade.ncu-rep --page source --csv --print-source sass > sass.csv
    tools/sass-lines.py dis.txt sass.csv SYMBOL_PART [SYMBOL_PART...] > OUT.csv

SYMBOL_PART: pieces of the kernel's mangled name, all of which pick its section of dis.txt.
Writes a CSV of the files, then the 40 lines with most stall samples: each with its share of
warp instructions, of thread instructions and of stall samples, and its IEEE divisions
(FCHK instructions, one per division, counted per thread).
"""
import collections
import csv
import re
import sys


def lines_of(disassembly, parts):
    """Offset -> ((file, line), instruction) for the kernel whose section names every part."""
    found, where, out = False, ("?", 0), {}
    for text in open(disassembly):
        if text.startswith(".text."):
            if found:
                break
            found = all(p in text for p in parts)
            continue
        if not found:
            continue
        m = re.match(r'\s*//## File "([^"]+)", line (\d+)', text)
        if m:
            where = (m.group(1), int(m.group(2)))
            continue
        m = re.match(r"\s*/\*([0-9a-f]{4,})\*/\s+(.*)", text)
        if m:
            out[int(m.group(1), 16)] = (where, m.group(2))
    if not out:
        sys.exit(f"no kernel in {disassembly} names all of {parts}")
    return out


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    disassembly, sass, parts = sys.argv[1], sys.argv[2], sys.argv[3:]
    source = lines_of(disassembly, parts)
    rows = [r for r in csv.reader(open(sass)) if len(r) > 5]
    header = rows[0]
    column = {name: header.index(name) for name in (
        "Address", "Instructions Executed", "Thread Instructions Executed",
        "Warp Stall Sampling (All Samples)")}
    rows = rows[1:]
    base = int(rows[0][column["Address"]], 16)
    # The kernel's first instruction runs once in every thread of the launch.
    threads = max(1, int(rows[0][column["Thread Instructions Executed"]].replace(",", "")))
    sums = {key: collections.Counter() for key in ("warp", "thread", "samples", "divisions")}
    by_file = {key: collections.Counter() for key in sums}
    for r in rows:
        where, instruction = source[int(r[column["Address"]], 16) - base]
        values = {
            "warp": int(r[column["Instructions Executed"]].replace(",", "")),
            "thread": int(r[column["Thread Instructions Executed"]].replace(",", "")),
            "samples": int(r[column["Warp Stall Sampling (All Samples)"]].replace(",", "")),
        }
        values["divisions"] = values["thread"] if "FCHK" in instruction else 0
        for key, value in values.items():
            sums[key][where] += value
            by_file[key][where[0]] += value
    total = {key: sum(c.values()) or 1 for key, c in sums.items()}
    out = csv.writer(sys.stdout)
    out.writerow(["file", "line", "warp_instructions_pct", "thread_instructions_pct",
                  "stall_samples_pct", "divisions_per_thread_of_the_launch"])
    for name, _ in by_file["warp"].most_common():
        out.writerow([name, "all"] + [f"{100 * by_file[k][name] / total[k]:.1f}"
                                      for k in ("warp", "thread", "samples")] +
                     [f"{by_file['divisions'][name] / threads:.2f}"])
    for where, _ in sums["samples"].most_common(40):
        out.writerow([where[0], where[1]] + [f"{100 * sums[k][where] / total[k]:.1f}"
                                             for k in ("warp", "thread", "samples")] +
                     [f"{sums['divisions'][where] / threads:.2f}"])


if __name__ == "__main__":
    main()
