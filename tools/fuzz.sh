#!/usr/bin/env bash
# Fuzzes the course's file readers with libFuzzer, under AddressSanitizer and
# UndefinedBehaviorSanitizer: chapter 05's OBJ loader, starting from the files in
# tests/05_obj_loading/corpus/, then chapter 07's ray-file reader, starting from a few ray files
# this script writes.
#   tools/fuzz.sh [obj-seconds] [ray-seconds]     (default 30 and 15)
# Needs clang and libFuzzer (Debian: clang, libclang-rt-dev); no CUDA toolkit and no GPU: both
# readers are plain C++ (this script compiles them without CUDA's headers). Exits non-zero on
# any crash, leak, undefined behaviour, timeout or broken invariant; the input that caused it
# is saved in build/fuzz/ (replay: build/fuzz/fuzz_obj FILE or build/fuzz/fuzz_rays FILE).
set -euo pipefail
cd "$(dirname "$0")/.."
obj_seconds="${1:-30}"
ray_seconds="${2:-15}"
out=build/fuzz
mkdir -p "$out/found" "$out/found_rays" "$out/ray_seeds"

if ! command -v clang++ >/dev/null; then
  echo "error: clang++ not found; install clang and libclang-rt-dev (tools/install-deps.sh)" >&2
  exit 1
fi

flags=(-std=c++20 -g -O1 -fno-omit-frame-pointer "-fsanitize=address,undefined"
       -fno-sanitize-recover=all)
includes=(-Icommon/include -Ichapters/03_spheres -Ichapters/04_moller_trumbore
          -Ichapters/05_obj_loading -Ichapters/07_bvh -Itests/05_obj_loading)

compile() { # source file, object file
  clang++ "${flags[@]}" -fsanitize=fuzzer-no-link -DTINYOBJLOADER_USE_DOUBLE -Wall -Wextra \
    "${includes[@]}" -c "$1" -o "$2"
}
link() { # target name, its source, objects...
  local name="$1" source="$2"
  shift 2
  if ! clang++ "${flags[@]}" -fsanitize=fuzzer "${includes[@]}" "$source" "$@" -lz \
    -o "$out/$name"; then
    echo "error: linking with libFuzzer failed; install libclang-rt-dev (tools/install-deps.sh)" >&2
    exit 1
  fi
}

# tinyobjloader is compiled here from the system's header (Debian's libtinyobjloader-dev), with
# the same instrumentation: the fuzzer then sees its branches, and the sanitizers its bugs.
printf '#define TINYOBJLOADER_IMPLEMENTATION\n#include <tiny_obj_loader.h>\n' \
  > "$out/tinyobjloader.cpp"
clang++ "${flags[@]}" -fsanitize=fuzzer-no-link -DTINYOBJLOADER_USE_DOUBLE -w \
  -c "$out/tinyobjloader.cpp" -o "$out/tinyobjloader.o"
obj_objects=("$out/tinyobjloader.o")
for source in chapters/05_obj_loading/{obj_loader,obj_checks,gunzip}.cpp \
  chapters/04_moller_trumbore/mesh_gen.cpp \
  common/src/cpu_progress.cpp; do
  compile "$source" "$out/$(basename "$source" .cpp).o"
  obj_objects+=("$out/$(basename "$source" .cpp).o")
done
link fuzz_obj tests/05_obj_loading/fuzz_obj.cpp "${obj_objects[@]}"
ray_objects=()
for source in chapters/07_bvh/ray_io.cpp common/src/output_file.cpp; do
  compile "$source" "$out/$(basename "$source" .cpp).o"
  ray_objects+=("$out/$(basename "$source" .cpp).o")
done
link fuzz_rays tests/07_bvh/fuzz_rays.cpp "${ray_objects[@]}"

# Seeds for the ray reader: a good ray file, one with a NaN, one a byte short of two rays.
python3 - "$out/ray_seeds" <<'PY'
import struct, sys
good = struct.pack("<8f", 0, 1, 2, 0, 0, -1, 0, float("inf"))
far = struct.pack("<8f", -5e9, 0, 0, 1e-4, 1e4, 0, -1, 3)
bad = struct.pack("<8f", 0, float("nan"), 0, 1, 0, 0, 0, 1)
for name, data in [("good", good + far), ("nan", good + bad), ("ragged", (good + far)[:-1])]:
    open(f"{sys.argv[1]}/{name}.rays", "wb").write(data)
PY

# New inputs go to build/fuzz/found*; the committed corpus is only read.
export ASAN_OPTIONS="detect_leaks=1:allocator_may_return_null=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
echo "== the OBJ loader, ${obj_seconds} s"
"$out/fuzz_obj" -max_total_time="$obj_seconds" -timeout=10 -rss_limit_mb=2048 -max_len=65536 \
  -print_final_stats=1 -artifact_prefix="$out/" "$out/found" tests/05_obj_loading/corpus
echo "== the ray-file reader, ${ray_seconds} s"
"$out/fuzz_rays" -max_total_time="$ray_seconds" -timeout=10 -rss_limit_mb=2048 -max_len=4096 \
  -print_final_stats=1 -artifact_prefix="$out/" "$out/found_rays" "$out/ray_seeds"
