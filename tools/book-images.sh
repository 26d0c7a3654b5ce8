#!/usr/bin/env bash
# Makes every image in book/images by running the chapters headless on the CPU backend, so
# every picture in the book can be regenerated (and is the same on any machine).
#   tools/book-images.sh [preset]     (default preset: default)
set -euo pipefail
cd "$(dirname "$0")/.."
source tools/env.sh
preset="${1:-default}"
cmake --preset "$preset" >/dev/null
cmake --build --preset "$preset"
bin="build/$preset/bin"
img=book/images
mkdir -p "$img"

# Chapter 01: 200x120 pixels in blocks of 16x16; neither side is a multiple of 16, so the grid
# hangs over both edges and the flat offset check wraps rows.
"$bin/ch01_kernel_launch" --backend cpu --width 200 --height 120 --block 16x16 --frames 1 \
  --output "$img/01_block_pattern.png" --flat-output "$img/01_flat_offset_check.png"

# Chapter 02: the animation's frame 119 at 480x270, headless.
"$bin/ch02_pbo_interop" --headless --backend cpu --width 480 --height 270 --frames 120 \
  --output "$img/02_frame.png"
