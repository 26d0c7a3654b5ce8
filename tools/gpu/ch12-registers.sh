#!/usr/bin/env bash
# Chapter 12's register experiment (the book's lab notes): builds ch12_materials once per cap on
# the registers of its kernels (RT_CH12_MAX_REGISTERS; 0 is ptxas's own choice), in parallel,
# and runs each headless at 1920x1080 on the material room, writing one report per cap.
#   tools/gpu/ch12-registers.sh OUTDIR [CAPS...]      (default caps: 0 128 96 80 64)
# Run it after tools/gpu/run.sh on a machine without the Debian libraries: it reuses the private
# prefix that run.sh unpacked (RT_PREFIX, default /tmp/rt-prefix).
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
cd "$root"
source tools/env.sh
out="$(realpath -m "${1:?an output folder}")"
shift
caps=("$@")
[ ${#caps[@]} -gt 0 ] || caps=(0 128 96 80 64)
mkdir -p "$out"
prefix="${RT_PREFIX:-/tmp/rt-prefix}"
args=()
if [ -d "$prefix/usr" ]; then
  libs="$prefix/usr/lib/x86_64-linux-gnu"
  export LD_LIBRARY_PATH="$libs:$libs/pulseaudio:$prefix/lib/x86_64-linux-gnu${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
  export CPATH="$prefix/usr/include/x86_64-linux-gnu${CPATH:+:$CPATH}"
  export PATH="$prefix/usr/bin:$PATH"
  args+=("-DCMAKE_PREFIX_PATH=$prefix/usr")
fi
for cap in "${caps[@]}"; do
  (cmake -S . -B "build/registers$cap" -G Ninja -DCMAKE_BUILD_TYPE=Release \
     -DCMAKE_CUDA_ARCHITECTURES=native -DRT_BUILD_TESTS=OFF -DRT_CH12_MAX_REGISTERS="$cap" \
     "${args[@]}" >"$out/configure$cap.log" 2>&1 &&
   cmake --build "build/registers$cap" --target ch12_materials >"$out/build$cap.log" 2>&1) &
done
wait
for cap in "${caps[@]}"; do
  echo "== registers at most $cap (0: no cap)"
  "build/registers$cap/bin/ch12_materials" --backend gpu --headless --width 1920 --height 1080 \
    --frames 20 --output "" --json "$out/registers$cap.json" | grep -E "persistent|megakernel|wavefront|chapter 11"
done
