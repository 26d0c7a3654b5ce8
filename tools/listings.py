#!/usr/bin/env python3
"""Keeps the book's code listings identical to the code they show.

A listing in book/*.md is an HTML comment naming a marked region of a source file, followed by
a fenced code block:

    <!-- listing: chapters/01_kernel_launch/first_kernel.cu first_kernel -->
    ```cuda
    ...filled in by this tool...
    ```

In the source the region sits between `// [listing:NAME]` and `// [/listing:NAME]` (or `#`
comments). Marker lines inside a region are left out of the listing.

    tools/listings.py          fill every listing from the code
    tools/listings.py --check  fail if a listing differs from the code, names a missing file or
                               region, or a marked region is shown nowhere in the book
"""
import argparse
import pathlib
import re
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
SOURCE_DIRS = ["common", "chapters", "tests", "tools", "cmake", "assets"]
SOURCE_SUFFIXES = {".h", ".cuh", ".cpp", ".cu", ".cmake", ".txt", ".sh", ".py"}
MARKER = re.compile(r"^\s*(?://|#)\s*\[(/?)listing:([\w-]+)\]\s*$")
DIRECTIVE = re.compile(r"^<!-- listing: (\S+) ([\w-]+) -->$")


class ListingError(Exception):
    pass


def regions_in(path):
    """All marked regions of one source file: {name: [lines]}."""
    regions, open_regions = {}, {}
    for number, line in enumerate(path.read_text().splitlines(), 1):
        match = MARKER.match(line)
        if not match:
            for lines in open_regions.values():
                lines.append(line)
            continue
        closing, name = match.groups()
        if not closing:
            if name in regions or name in open_regions:
                raise ListingError(f"{path.relative_to(ROOT)}:{number}: region '{name}' marked twice")
            open_regions[name] = []
        elif name not in open_regions:
            raise ListingError(f"{path.relative_to(ROOT)}:{number}: '{name}' closed but never opened")
        else:
            regions[name] = dedent(open_regions.pop(name))
    if open_regions:
        raise ListingError(f"{path.relative_to(ROOT)}: region(s) never closed: {sorted(open_regions)}")
    return regions


def dedent(lines):
    indents = [len(l) - len(l.lstrip()) for l in lines if l.strip()]
    cut = min(indents, default=0)
    return [l[cut:] for l in lines]


def all_regions():
    found = {}
    for directory in SOURCE_DIRS:
        for path in sorted((ROOT / directory).rglob("*")):
            if path.is_file() and path.suffix in SOURCE_SUFFIXES and path.name != "listings.py":
                for name, lines in regions_in(path).items():
                    found[(str(path.relative_to(ROOT)), name)] = lines
    return found


def process(page, regions, used, check):
    """Fills or checks the listings of one book page; returns the problems found."""
    problems, out = [], []
    lines = page.read_text().splitlines()
    i = 0
    while i < len(lines):
        out.append(lines[i])
        match = DIRECTIVE.match(lines[i].strip())
        i += 1
        if not match:
            continue
        where = f"{page.relative_to(ROOT)}:{i}"
        key = (match.group(1), match.group(2))
        if i >= len(lines) or not lines[i].startswith("```"):
            problems.append(f"{where}: a listing directive must be followed by a ``` block")
            continue
        end = next((j for j in range(i + 1, len(lines)) if lines[j].startswith("```")), None)
        if end is None:
            problems.append(f"{where}: unterminated code block")
            break
        if key not in regions:
            problems.append(f"{where}: no region '{key[1]}' in {key[0]}")
            out.extend(lines[i:end + 1])
        else:
            used.add(key)
            if lines[i + 1:end] != regions[key]:
                problems.append(f"{where}: listing '{key[1]}' differs from {key[0]}")
            out.append(lines[i])
            out.extend(regions[key])
            out.append(lines[end])
        i = end + 1
    if not check:
        text = "\n".join(out) + "\n"
        if text != page.read_text():
            page.write_text(text)
            print(f"filled {page.relative_to(ROOT)}")
    return problems


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="check only, change nothing")
    args = parser.parse_args()
    try:
        regions = all_regions()
    except ListingError as error:
        print(f"listings: {error}", file=sys.stderr)
        return 1
    used, problems = set(), []
    for page in sorted((ROOT / "book").glob("*.md")):
        problems += process(page, regions, used, args.check)
    for key in sorted(set(regions) - used):
        problems.append(f"{key[0]}: region '{key[1]}' is marked but no book page shows it")
    if not args.check:
        problems = [p for p in problems if "differs from" not in p]
    for problem in problems:
        print(f"listings: {problem}", file=sys.stderr)
    if problems:
        return 1
    print(f"listings: {len(used)} listings match the code")
    return 0


if __name__ == "__main__":
    sys.exit(main())
