#!/usr/bin/env bash
# Fuzzes the chapter 05 OBJ loader with libFuzzer, under AddressSanitizer and
# UndefinedBehaviorSanitizer, starting from the files in tests/05_obj_loading/corpus/.
#   tools/fuzz.sh [seconds]     (default 30)
# Needs clang and libFuzzer (Debian: clang, libclang-rt-dev); no GPU and no nvcc: the loader
# is plain C++. Exits non-zero on any crash, leak, undefined behaviour, timeout or broken mesh
# invariant; the input that caused it is saved in build/fuzz/ (replay: build/fuzz/fuzz_obj FILE).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-30}"
out=build/fuzz
mkdir -p "$out/found"

if ! command -v clang++ >/dev/null; then
  echo "error: clang++ not found; install clang and libclang-rt-dev (tools/install-deps.sh)" >&2
  exit 1
fi

flags=(-std=c++20 -g -O1 -fno-omit-frame-pointer "-fsanitize=address,undefined"
       -fno-sanitize-recover=all)
includes=(-Icommon/include -Ichapters/03_spheres -Ichapters/04_moller_trumbore
          -Ichapters/05_obj_loading -Itests/05_obj_loading)

# tinyobjloader is compiled here from the system's header (Debian's libtinyobjloader-dev), with
# the same instrumentation: the fuzzer then sees its branches, and the sanitizers its bugs.
printf '#define TINYOBJLOADER_IMPLEMENTATION\n#include <tiny_obj_loader.h>\n' \
  > "$out/tinyobjloader.cpp"
clang++ "${flags[@]}" -fsanitize=fuzzer-no-link -DTINYOBJLOADER_USE_DOUBLE -w \
  -c "$out/tinyobjloader.cpp" -o "$out/tinyobjloader.o"
objects=("$out/tinyobjloader.o")
for source in obj_loader obj_checks gunzip; do
  clang++ "${flags[@]}" -fsanitize=fuzzer-no-link -DTINYOBJLOADER_USE_DOUBLE -Wall -Wextra \
    "${includes[@]}" -c "chapters/05_obj_loading/$source.cpp" -o "$out/$source.o"
  objects+=("$out/$source.o")
done
if ! clang++ "${flags[@]}" -fsanitize=fuzzer "${includes[@]}" tests/05_obj_loading/fuzz_obj.cpp \
  "${objects[@]}" -lz -o "$out/fuzz_obj"; then
  echo "error: linking with libFuzzer failed; install libclang-rt-dev (tools/install-deps.sh)" >&2
  exit 1
fi

# New inputs go to build/fuzz/found; the committed corpus is only read.
export ASAN_OPTIONS="detect_leaks=1:allocator_may_return_null=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
"$out/fuzz_obj" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=65536 \
  -print_final_stats=1 -artifact_prefix="$out/" "$out/found" tests/05_obj_loading/corpus
