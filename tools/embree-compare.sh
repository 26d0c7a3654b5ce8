#!/usr/bin/env bash
# Chapter 07's optional comparison with Embree: builds ch07_embree_compare (only possible where
# Embree 3 is installed; Debian: apt-get install libembree-dev) and runs it on the benchmark
# set in models/ (tools/get-models.sh). The tables go to OUTDIR/embree-compare.md, the rows to
# .json.
#   tools/embree-compare.sh OUTDIR [options for ch07_embree_compare, e.g. --robust]
# Both tracers run on the CPU backend's threads: RT_CPU_THREADS=1 tools/embree-compare.sh ...
# measures both on one.
set -euo pipefail
cd "$(dirname "$0")/.."
source tools/env.sh
out="${1:?usage: tools/embree-compare.sh OUTDIR [program options]}"
shift
cmake --preset default >/dev/null
targets=$(cmake --build build/default --target help)
if ! grep -q '^ch07_embree_compare:' <<<"$targets"; then
  echo "embree-compare: Embree 3 was not found, so ch07_embree_compare is not built" >&2
  exit 1
fi
cmake --build build/default --target ch07_embree_compare
models=models
scenes=()
for name in conference sponza-dabrovic stanford-bunny armadillo-100k stanford-dragon; do
  if [ -f "$models/$name.obj.gz" ]; then scenes+=("$models/$name.obj.gz"); fi
done
if [ ${#scenes[@]} -eq 0 ]; then
  echo "embree-compare: no benchmark scenes in $models" >&2
  exit 1
fi
mkdir -p "$out"
build/default/bin/ch07_embree_compare --json "$out/embree-compare.json" "$@" "${scenes[@]}" |
  tee "$out/embree-compare.md"
