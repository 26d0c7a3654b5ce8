#!/usr/bin/env python3
"""Counts the load instructions of chapter 08's traversal kernels in a binary's machine code.

    tools/sass-loads.py BINARY           (runs cuobjdump -sass on it; needs the CUDA toolkit)
    tools/sass-loads.py --sass FILE      (reads the output of cuobjdump -sass from a file)

One line per kernel: its memory path and query, and how many of each load instruction the
compiler emitted (LDG: global, .128: 16-byte vector, .CONSTANT: read-only data cache; TEX/TLD:
texture unit; LDC: constant bank; LDL/STL: local memory, such as a stack that did not fit in
registers). Counts are of instructions in the code, not of executions.
"""
import collections
import re
import subprocess
import sys

PATHS = [("TextureRecords", "texture"), ("ReadOnlyRecords", "float4_ldg"),
         ("GlobalRecords", "float4"), ("ReadOnlyBvh", "ldg"), ("BvhView", "global")]


def kernel_label(mangled):
    if "camera_trace_kernel" in mangled:
        where = "kernel parameters" if "parameters" in mangled else "__constant__"
        return f"camera rays in the kernel (kept path), {where}"
    if "path_trace_kernel" not in mangled:
        return None
    path = next((name for key, name in PATHS if key in mangled), "?")
    query = re.search(r"QueryE(\d)", mangled)
    return f"{path}, {'any' if query and query.group(1) == '1' else 'closest'} hit"


def main():
    if len(sys.argv) == 3 and sys.argv[1] == "--sass":
        text = open(sys.argv[2]).read()
    elif len(sys.argv) == 2:
        text = subprocess.run(["cuobjdump", "-sass", sys.argv[1]], check=True,
                              capture_output=True, text=True).stdout
    else:
        sys.exit(__doc__)
    kernels = {}
    current = None
    for line in text.splitlines():
        header = re.search(r"Function : (\S+)", line)
        if header:
            label = kernel_label(header.group(1))
            current = collections.Counter() if label else None
            if label:
                kernels[label] = current
            continue
        if current is None:
            continue
        op = re.search(r"/\*[0-9a-f]{4,}\*/\s+(?:@!?U?P\w+\s+)?([A-Z][A-Z0-9_.]+)", line)
        if op and re.match(r"(LDG|LDL|STL|LDC|ULDC|TEX|TLD|LD\b|LD\.)", op.group(1)):
            current[op.group(1)] += 1
    if not kernels:
        sys.exit("sass-loads: no chapter 08 kernels in the machine code")
    for label in sorted(kernels):
        counts = ", ".join(f"{n} {op}" for op, n in sorted(kernels[label].items()))
        print(f"{label}: {counts}")


if __name__ == "__main__":
    main()
