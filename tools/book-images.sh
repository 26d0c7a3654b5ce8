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

scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT

# Chapter 01: 200x120 pixels in blocks of 16x16; neither side is a multiple of 16, so the grid
# hangs over both edges and the flat offset check wraps rows. The diagram: a grid of blocks
# over an image.
"$bin/ch01_kernel_launch" --backend cpu --width 200 --height 120 --block 16x16 --frames 1 \
  --output "$img/01_block_pattern.png" --flat-output "$img/01_flat_offset_check.png"
python3 tools/diagrams/ch01.py "$img"

# Chapter 02: the animation's frame 119 at 480x270, headless, and the same frame torn over
# frame 118 (the picture of reading the buffer while the kernel writes it). The diagrams: the
# three display paths across the bus, and the pixel buffer's life.
"$bin/ch02_pbo_interop" --headless --backend cpu --width 480 --height 270 --frames 120 \
  --output "$img/02_frame.png" --torn-output "$img/02_torn_frame.png"
python3 tools/diagrams/ch02.py "$img"

# Chapter 03: the default scene at 960x540 with the stable test (mirror depth 4). Failures:
# the farthest moon (1:3 000) zoomed in, through the textbook and the stable test; mirror rays
# started a fixed 1e-4 off the surface, with the scene scaled by 2^20 (a power of two, so that
# only the offset changes), and the scaled offset for comparison. The diagram: the stable
# test's geometry.
"$bin/ch03_spheres" --headless --backend cpu --width 960 --height 540 --frames 1 \
  --output "$img/03_spheres.png" >/dev/null
for variant in textbook stable; do
  "$bin/ch03_spheres" --headless --backend cpu --width 320 --height 180 --frames 1 \
    --target 3000,2500,-30000 --fov 0.05 --variant "$variant" \
    --output "$img/03_far_moon_$variant.png" >/dev/null
done
"$bin/ch03_spheres" --headless --backend cpu --width 480 --height 270 --frames 1 \
  --scale 1048576 --fixed-offset 1e-4 --output "$img/03_acne_fixed_offset.png" >/dev/null
"$bin/ch03_spheres" --headless --backend cpu --width 480 --height 270 --frames 1 \
  --scale 1048576 --output "$img/03_acne_scaled_offset.png" >/dev/null
python3 tools/diagrams/ch03.py "$img"

# Chapter 04: the demo scene at 960x540 with the watertight test; where a million rays aimed
# at the vertices and edges of each closed mesh leak through Moller-Trumbore (the report of
# that run is a small one); the diagram of the watertight test's frame.
"$bin/ch04_moller_trumbore" --headless --backend cpu --width 960 --height 540 --frames 1 \
  --leak-rays 1000 --output "$img/04_triangles.png" >/dev/null
"$bin/ch04_moller_trumbore" --headless --backend cpu --width 32 --height 18 --frames 1 \
  --variant moller-trumbore --leak-map "$img/04_leaks_moller_trumbore.png" \
  --output "$scratch/04_small.png" >/dev/null
python3 tools/diagrams/ch04.py "$img"

# Chapter 05: the course's 100 000-triangle torus knot, framed automatically, brute force on the
# CPU (minutes on a few cores); the report traces a small sample only.
"$bin/ch05_obj_loading" --headless --backend cpu --width 480 --height 270 \
  --reference-pixels 2000 --scaling-max -1 --output "$img/05_model.png" >/dev/null

# ...and the original loader's two index mistakes on the Cornell room, beside the right load.
for mistake in none minus-one file-order; do
  "$bin/ch05_obj_loading" --headless --backend cpu --width 320 --height 240 \
    --scene assets/cornell_room.obj.gz --index-mistake "$mistake" --reference-pixels 1000 \
    --scaling-max -1 --output "$img/05_index_$mistake.png" >/dev/null
done

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

# The shadow terminator on an 80-triangle sphere lit from the side, without and with the lift.
for lift in off on; do
  "$bin/ch06_lambertian_shading" --headless --backend cpu --width 480 --height 270 \
    --subdivisions 1 --point-light off --light-dir 1,0.15,0.25 --eye -1.2,1.6,3.6 \
    --target -1.2,1.0,0 --fov 30 --terminator-lift "$lift" --image-only \
    --output "$img/06_terminator_lift_$lift.png" >/dev/null
done

# Chapter 07: the torus knot shaded through the tree, at 960x540 on the CPU (seconds, where
# chapter 05's brute force took minutes for a quarter of the pixels).
"$bin/ch07_bvh" --headless --backend cpu --width 960 --height 540 --image-only \
  --output "$img/07_knot.png" >/dev/null

# Chapter 07: nodes visited per camera ray, through the median and the SAH tree.
for split in median sah; do
  "$bin/ch07_bvh" --headless --backend cpu --width 480 --height 270 --image-only --heat-map \
    --split "$split" --output "$img/07_heat_$split.png" >/dev/null
done
# Chapter 09: the same view's heat map through the compressed 8-wide tree, in chapter 07's
# colours (wide nodes visited per camera ray).
"$bin/ch09_wide_bvh" --headless --backend cpu --width 480 --height 270 --image-only --heat-map \
  --output "$img/09_heat_wide.png" >/dev/null

# Chapter 11: the Cornell room at 512 samples per pixel, and at 16 with each strategy for
# direct light (bounces only, shadow rays only, both weighted by MIS); then its error against
# run time on the CPU, measured here (the JSON goes to book/data, the plot below). Chapters 11
# and 12's pictures are drawn with the independent sampler, the numbers their text describes
# (the programs' default is chapter 11b's sobol sampler).
"$bin/ch11_path_tracing" --headless --backend cpu --width 320 --height 240 --spp 512 \
  --sampler independent --image-only --output "$img/11_room.png" >/dev/null
# Bounces alone at 28 samples: about the time of MIS's 16 (the convergence table's costs).
"$bin/ch11_path_tracing" --headless --backend cpu --width 320 --height 240 --spp 28 \
  --sampler independent --strategy bsdf --image-only \
  --output "$img/11_equal_time_bsdf.png" >/dev/null
for strategy in bsdf light mis; do
  "$bin/ch11_path_tracing" --headless --backend cpu --width 320 --height 240 --spp 16 \
    --sampler independent --strategy "$strategy" --image-only \
    --output "$img/11_strategy_$strategy.png" >/dev/null
done
# The room with the independent sampler at 160x120: 1, 4, 16 and 256 samples per pixel (MIS),
# and at 4 samples bounces alone and shadow rays alone, where the fireflies show.
for spp in 1 4 16 256; do
  "$bin/ch11_path_tracing" --headless --backend cpu --image-only --sampler independent \
    --width 160 --height 120 --spp "$spp" --output "$img/11_spp_$spp.png" >/dev/null
done
for strategy in bsdf light; do
  "$bin/ch11_path_tracing" --headless --backend cpu --image-only --sampler independent \
    --width 160 --height 120 --spp 4 --strategy "$strategy" \
    --output "$img/11_spp4_$strategy.png" >/dev/null
done
# The white furnace: a closed cube whose faces (wound to face inwards) have albedo 0.8 and emit
# 0.2, seen from inside at 16 samples per pixel by each strategy; every pixel's mean is
# Le / (1 - a) = 1, the cube's edges vanish, and only the noise differs.
python3 - "$scratch" <<'PYTHON'
import sys, pathlib
out = pathlib.Path(sys.argv[1])
# A closed cube [-1, 1]^3 whose faces are wound to face inwards (counter-clockwise seen from
# inside), every face albedo 0.8 and emitting 0.2: inside, L = Le / (1 - a) = 1 everywhere.
v = [(x, y, z) for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)]
index = {p: i + 1 for i, p in enumerate(v)}
faces = []
for axis in range(3):
    for side in (-1, 1):
        corners = [p for p in v if p[axis] == side]
        a, b = [i for i in range(3) if i != axis]
        around = {(-1, -1): 0, (1, -1): 1, (1, 1): 2, (-1, 1): 3}
        ring = sorted(corners, key=lambda p: around[(p[a], p[b])])
        # counter-clockwise in (a, b) seen from +axis: the + face must turn the other way
        if (side > 0) == ((a, b) in ((1, 2), (2, 0), (0, 1))):
            ring = ring[::-1]
        i = [index[p] for p in ring]
        faces += [(i[0], i[1], i[2]), (i[0], i[2], i[3])]
(out / "furnace_box.mtl").write_text("newmtl furnace\nKd 0.8 0.8 0.8\nKe 0.2 0.2 0.2\n")
with open(out / "furnace_box.obj", "w") as f:
    f.write("mtllib furnace_box.mtl\n")
    for p in v:
        f.write("v %d %d %d\n" % p)
    f.write("usemtl furnace\n")
    for t in faces:
        f.write("f %d %d %d\n" % t)
PYTHON
for strategy in bsdf light mis; do
  "$bin/ch11_path_tracing" --headless --backend cpu --sampler independent \
    --scene "$scratch/furnace_box.obj" --eye 0.3,0.2,0.1 --target 0.3,0.2,-1 --fov 100 \
    --width 160 --height 120 --spp 16 --strategy "$strategy" --image-only --exposure 0.5 \
    --output "$img/11_furnace_$strategy.png" >/dev/null
done
"$bin/ch11_path_tracing" --headless --backend cpu --convergence --width 64 --height 48 \
  --spp 256 --reference-spp 4096 --json book/data/11_path_tracing_convergence.json >/dev/null
python3 tools/plot-convergence.py --title "Chapter 11: relative MSE against time (CPU, 64x48)" \
  --out "$img/11_convergence.svg" book/data/11_path_tracing_convergence.json
# ...chapter 10's moving scene, its 30th frame at 64 samples per pixel (seconds on the CPU)...
"$bin/ch11_path_tracing" --moving --headless --backend cpu --image-only --frames 30 \
  --sampler independent --width 320 --height 180 --sun 0.4,1,0.3 --sky 0.6 --spp 64 \
  --output "$img/11_moving.png" >/dev/null
# ...and the error against run time of the three scenes on an H200, against the kernels' time
# (book/data, from tools/gpu/run.sh's bench11 step).
convergence_h200() {
  local scene="$1" name="$2"
  python3 tools/plot-convergence.py --time kernel_ms \
    --title "Chapter 11: $name (H200, 320x240)" \
    --out "$img/11_convergence_h200_$scene.svg" "book/data/11_convergence_h200_$scene.json"
}
convergence_h200 room "the Cornell room"
convergence_h200 sponza "Sponza in sunlight"
convergence_h200 conference "the conference room"

# Chapter 11b: the samplers' own points, written by ch11_sample_points (16, 64 and 256 samples
# of one pixel by each sampler; zsobol's first sample of every pixel of an 8x8 image, with its
# order); the room at 256x256 and 4 samples per pixel by each sampler, as a picture and as
# radiance, and a reference of 2 048 samples (a few minutes on 2 cores). The script draws the
# points, the nets, the discrepancy, Owen's tree, the Morton order, the error images and their
# spectra, and the error against samples from book/data/11b_samplers_cpu_room.json, a measured
# report kept as data (its run takes minutes: ch11_path_tracing --backend cpu --headless
# --convergence --samplers --width 160 --height 120 --spp 256 --reference-spp 8192 --json ...).
for sampler in independent stratified sobol zsobol; do
  for count in 16 64 256; do
    "$bin/ch11_sample_points" --sampler "$sampler" --count "$count" \
      --output "$scratch/11b_points_${sampler}_$count.csv" >/dev/null
  done
  for output in "$scratch/11b_room_$sampler.pfm" "$scratch/11b_room_$sampler.png"; do
    "$bin/ch11_path_tracing" --headless --backend cpu --width 256 --height 256 --spp 4 \
      --sampler "$sampler" --image-only --output "$output" >/dev/null
  done
done
"$bin/ch11_sample_points" --sampler zsobol --count 1 --width 8 --height 8 --image \
  --order "$scratch/11b_zsobol_order.csv" --output "$scratch/11b_zsobol_image.csv" >/dev/null
"$bin/ch11_path_tracing" --headless --backend cpu --width 256 --height 256 --spp 2048 \
  --sampler sobol --image-only --output "$scratch/11b_room_reference.pfm" >/dev/null
python3 tools/diagrams/ch11b.py "$img" "$scratch" book/data/11b_samplers_cpu_room.json

# Chapter 12: the material room (its glTF camera) at 320x240 and 128 samples per pixel; the
# roughness series of gold, glass and a white metal, the metal and the glass also without
# energy compensation; the chi-square maps of three samplers (observed | expected | a wrong
# twin); the furnace spheres as radiance (.pfm), the camera inside the glass one, and rough
# glass with and without its compensation, drawn in false colour by the chapter's diagram
# script; and aliasing along a floor whose checkerboard is 16 times finer than the room's
# (128 squares a side on 1024 texels, from tools/make-material-room.py's checkerboard),
# point-sampled and trilinear, at 4 samples per pixel.
"$bin/ch12_materials" --headless --backend cpu --width 320 --height 240 --spp 128 \
  --sampler independent --image-only --output "$img/12_room.png" >/dev/null
for series in gold glass white-metal; do
  "$bin/ch12_materials" --headless --backend cpu --series "$series" --width 480 --height 192 \
    --sampler independent --spp 64 --image-only --output "$img/12_series_$series.png" >/dev/null
done
for series in white-metal glass; do
  "$bin/ch12_materials" --headless --backend cpu --series "$series" --no-compensation \
    --sampler independent --width 480 --height 192 --spp 64 --image-only \
    --output "$img/12_series_${series}_no_compensation.png" >/dev/null
done
"$bin/ch12_chi2_maps" --material rough-glass --roughness 0.5 --theta 50 \
  --output "$img/12_chi2_rough_glass.png" >/dev/null
"$bin/ch12_chi2_maps" --material gold --roughness 0.3 --theta 60 \
  --output "$img/12_chi2_gold.png" >/dev/null
"$bin/ch12_chi2_maps" --material white --theta 30 --output "$img/12_chi2_white.png" >/dev/null
furnace() {
  local name="$1"
  shift
  "$bin/ch12_materials" --headless --backend cpu --width 128 --height 128 --spp 64 \
    --sampler independent --image-only --output "$scratch/12_furnace_$name.pfm" "$@" >/dev/null
}
furnace glass --furnace glass
furnace rough_glass --furnace rough-glass --roughness 0.6
furnace metal --furnace white-metal --roughness 1
furnace metal_plain --furnace white-metal --roughness 1 --no-compensation
furnace inside --furnace glass --eye 0,0,0 --target 0,0,-1
# Rough glass of index 1.5 in the furnace at five roughnesses, one scattering only and with
# Turquin's scale (12_furnace_glass.png).
for roughness in 0 0.25 0.5 0.75 1; do
  "$bin/ch12_materials" --headless --backend cpu --width 64 --height 64 --spp 64 \
    --sampler independent --image-only --furnace rough-glass --roughness "$roughness" \
    --output "$scratch/12_furnace_glass_${roughness}_compensated.pfm" >/dev/null
  "$bin/ch12_materials" --headless --backend cpu --width 64 --height 64 --spp 64 \
    --sampler independent --image-only --furnace rough-glass --roughness "$roughness" \
    --no-compensation --output "$scratch/12_furnace_glass_${roughness}_plain.pfm" >/dev/null
done
python3 tools/diagrams/ch12.py "$img" "$scratch"
cp assets/material_room.gltf "$scratch/"
python3 - "$scratch/material_room_floor.png" <<'PYTHON'
import importlib.util, sys
spec = importlib.util.spec_from_file_location("room", "tools/make-material-room.py")
room = importlib.util.module_from_spec(spec)
spec.loader.exec_module(room)
open(sys.argv[1], "wb").write(room.checkerboard(side=1024, squares=128))
PYTHON
for filter in point trilinear; do
  "$bin/ch12_materials" --headless --backend cpu --scene "$scratch/material_room.gltf" \
    --sampler independent --width 320 --height 180 --spp 4 --filter "$filter" --eye 0.9,0.1,0.97 \
    --target -0.2,0,-1 --fov 45 --image-only --output "$img/12_aliasing_$filter.png" >/dev/null
done
# ...and the room's error against run time on an H200 (book/data, from tools/gpu/run.sh's
# bench12 step).
python3 tools/plot-convergence.py --time kernel_ms \
  --title "Chapter 12: relative MSE against GPU time, the material room (H200, 320x240)" \
  --out "$img/12_convergence_h200_room.svg" book/data/12_materials_h200_convergence_room.json

# Diagrams of chapters 05 on, one script per chapter (matplotlib; chapter 08's also plots
# book/data: each memory path against plain loads, and __ldg's loss on the 16-byte loads on the
# H100 and the H200); chapters 01-04 drew theirs above. Chapter 09's: its compressed node byte
# by byte, the collapse, a child box on its parent's grid, octant order, a warp's lanes, and the
# three warp-busy variants plotted from book/data/09_benchmark_h200.json.
for n in 05 06 07 08 09 11; do python3 "tools/diagrams/ch$n.py" "$img"; done

# Chapter 10: the moving scene's 90th frame; the diagrams (the Morton curve over the torus
# knot's centroids, read from assets/torus_knot_100k.obj.gz; the sorted codes' splits; Karras's
# tree; PLOC's rounds on a dozen points) with the plots of rebuild against refit (from the frames
# measured on the CPU, book/data/10_animation_cpu.csv, and on an H200,
# book/data/10_animation_h200.csv and 10_animation_dragon_h200.csv).
"$bin/ch10_gpu_build" --moving --backend cpu --frames 90 --update rebuild --width 320 \
  --height 180 --output "$img/10_moving.png" >/dev/null
python3 tools/diagrams/ch10.py "$img"

# Error-against-run-time plots, from the reports measured on a GPU machine (book/data/, written
# by tools/gpu/run.sh's --json runs and copied there).
python3 tools/plot-report.py --metric max_relative_t_error --ylabel "max relative t error" \
  --title "Chapter 03: hit distance error against time per frame (1920x1080)" \
  --out "$img/03_error_vs_time.svg" book/data/03_spheres.json
python3 tools/plot-report.py --metric leaks --per rays --rows "leaks," \
  --ylabel "leaks per million rays" --xlabel "ms per million rays" \
  --title "Chapter 04: leaks against time per million rays" \
  --out "$img/04_leaks_vs_time.svg" book/data/04_moller_trumbore.json
# Chapter 07's rows all have the same error: its plot puts the work per ray against the time
# (brute force's rows carry no count: it tests all 100 000 triangles).
python3 tools/plot-report.py --metric triangles_per_ray --rows "brute force" --rows "BVH" \
  --missing 100000 --ylabel "triangle tests per ray" \
  --title "Chapter 07: triangle tests per ray against time per frame (1280x720)" \
  --out "$img/07_work_vs_time.svg" book/data/07_bvh.json

# The closing chapter: a schematic of software against hardware traversal, and chapter 09's
# 4-wide packed tree against OptiX on the H200 (book/data/09_benchmark_h200.json, anchors.json).
python3 tools/diagrams/closing.py "$img"

# Chapter 13: a forest of a hundred torus knots (10 000 002 triangles as placed, 100 002
# stored), a million 320-triangle icospheres (--small), and the instanced shelf's glTF node
# graph (assets/instanced_shelf.gltf), each shaded with shadow rays on the CPU, small, without
# the flattened scene the report compares against (--flat-limit 0). The diagrams: one mesh in
# object and world space with a ray in both, the top level over eight instances, the two-level
# walk, and a small sphere far from the origin flattened to the float grid (numpy).
"$bin/ch13_instancing" --headless --backend cpu --instances 100 --width 640 --height 360 \
  --frames 1 --flat-limit 0 --output "$img/13_forest.png" >/dev/null
"$bin/ch13_instancing" --headless --backend cpu --small --instances 1000000 --width 320 \
  --height 180 --frames 1 --flat-limit 0 --output "$img/13_million.png" >/dev/null
"$bin/ch13_instancing" --headless --backend cpu --scene assets/instanced_shelf.gltf --width 640 \
  --height 360 --frames 1 --flat-limit 0 --output "$img/13_shelf.png" >/dev/null
"$bin/ch13_instancing" --headless --backend cpu --instances 30 --width 480 --height 270 \
  --spp 64 --frames 1 --flat-limit 0 --output "$img/13_paths.png" >/dev/null
python3 tools/diagrams/ch13.py "$img"
