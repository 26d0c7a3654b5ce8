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

# Chapter 03: the default scene at 960x540 with the stable test (mirror depth 4).
"$bin/ch03_spheres" --headless --backend cpu --width 960 --height 540 --frames 1 \
  --output "$img/03_spheres.png" >/dev/null

# Chapter 04: the demo scene at 960x540 with the watertight test.
"$bin/ch04_moller_trumbore" --headless --backend cpu --width 960 --height 540 --frames 1 \
  --leak-rays 1000 --output "$img/04_triangles.png" >/dev/null

# Chapter 05: the course's 100 000-triangle torus knot, framed automatically, brute force on the
# CPU (minutes on a few cores); the report traces a small sample only.
"$bin/ch05_obj_loading" --headless --backend cpu --width 480 --height 270 \
  --reference-pixels 2000 --scaling-max -1 --output "$img/05_model.png" >/dev/null

# Chapter 06: the built-in scene at 480x270, flat and smooth shading (shadows on).
"$bin/ch06_lambertian_shading" --headless --backend cpu --width 480 --height 270 --shading flat \
  --image-only --output "$img/06_flat.png" >/dev/null
"$bin/ch06_lambertian_shading" --headless --backend cpu --width 480 --height 270 \
  --shading smooth --image-only --output "$img/06_smooth.png" >/dev/null

# ...and a model loaded from a file, with its own vertex normals.
for shading in flat smooth; do
  "$bin/ch06_lambertian_shading" --headless --backend cpu --width 480 --height 270 \
    --scene assets/smooth_torus.obj.gz --eye 0,3.2,3.2 --target 0,0,0 --shading "$shading" \
    --image-only --output "$img/06_torus_$shading.png" >/dev/null
done

# Chapter 07: the torus knot shaded through the tree, at 960x540 on the CPU (seconds, where
# chapter 05's brute force took minutes for a quarter of the pixels).
"$bin/ch07_bvh" --headless --backend cpu --width 960 --height 540 --image-only \
  --output "$img/07_knot.png" >/dev/null

# Error-against-run-time plots, from the reports measured on a GPU machine (book/data/, written
# by tools/gpu/run.sh's --json runs and copied there).
python3 tools/plot-report.py --metric max_relative_t_error --ylabel "max relative t error" \
  --title "Chapter 03: hit distance error against time per frame (1920x1080)" \
  --out "$img/03_error_vs_time.svg" book/data/03_spheres.json
python3 tools/plot-report.py --metric leaks --per rays --rows "leaks," \
  --ylabel "leaks per million rays" --xlabel "ms per million rays" \
  --title "Chapter 04: leaks against time per million rays" \
  --out "$img/04_leaks_vs_time.svg" book/data/04_moller_trumbore.json
python3 tools/plot-report.py --metric max_rel_t_error --ylabel "max relative t error" \
  --title "Chapter 07: t error (sampled rays) against time per frame (1280x720)" \
  --out "$img/07_error_vs_time.svg" book/data/07_bvh.json
