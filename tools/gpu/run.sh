#!/usr/bin/env bash
# The GPU-machine run: on any Linux machine with an NVIDIA GPU, builds the course for that GPU,
# runs every test (the [gpu] ones too), runs compute-sanitizer's memcheck on each chapter
# executable and runs each chapter's report (its benchmark), writing logs to a folder.
#
#   tools/gpu/run.sh [LOGDIR]           (default LOGDIR: gpu-logs)
#
# RT_STEPS picks what runs after the build (default: all of them, in this order):
#   tests memcheck reports window window11 models bench bench08 bench09 bench10 bench11 samplers bench12 bench13 sass profile
# `models` renders the real models of RT_MODELS (default: models/, filled by tools/get-models.sh,
# else .gpu-models, filled by tools/gpu/pack-models.sh) with chapters 05 and 06, headless and in
# the window; `bench` runs chapter 07's benchmark protocol on them, `bench08` chapter 08's
# memory paths, `bench09` chapter 09's wide trees against the binary one, `bench10` chapter 10's
# builders on the benchmark set and its moving scene, rebuilt against refitted, `bench11` chapter
# 11's kernels at 1920x1080 and its convergence report, `bench12` chapter 12's material room at
# 1920x1080 (its kernels, chapter 11's tracer on the same geometry, the texture filters and
# reads) and its convergence report; `samplers` chapter 11's samplers (error against run time by
# sampler on the room, Sponza and the conference room; each sampler's time per sample at
# 1920x1080) and chapter 12's material room by sampler; `bench13` chapter 13's forests of
# instances (10 000 dragons, a million spheres, 16 dragons against the flattened scene);
# `window11` opens chapter 11 in the
# window at 1920x1080 on Sponza and the conference room (its frame rate), and the moving scenes
# of chapters 10 and 11, and chapter 13's turning forest. `sass` counts the
# load instructions of chapter 08's kernels in the machine code (cuobjdump); `profile` reads their
# cache hit rates with Nsight Compute (ncu), where it runs.
#
# Offline machines: run tools/gpu/fetch-debs.sh where there is internet, copy .gpu-debs/ (and
# .gpu-x11/ for the window test) along; this script unpacks them into private prefixes
# (RT_PREFIX, default /tmp/rt-prefix).
set -uo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
cd "$root"
logdir="$(realpath -m "${1:-gpu-logs}")"
mkdir -p "$logdir"
source tools/env.sh
status=0
steps=" ${RT_STEPS:-tests memcheck reports window window11 models bench bench08 bench09 bench10 bench11 samplers bench12 bench13 sass profile} "
wanted() { [[ "$steps" == *" $1 "* ]]; }
models="${RT_MODELS:-}"
if [ -z "$models" ]; then
  models="$root/.gpu-models"
  for model in "$root"/models/*.obj.gz; do # a link whose target stayed behind does not count
    if [ -r "$model" ]; then models="$root/models"; break; fi
  done
fi
step() { # step NAME COMMAND...: runs a command, logs it, remembers a failure
  local name=$1; shift
  echo "== $name: $*"
  if "$@" >"$logdir/$name.log" 2>&1; then echo "   ok"; else echo "   FAILED (see $name.log)"; tail -30 "$logdir/$name.log"; status=1; fi
}

debs="${RT_DEBS:-$root/.gpu-debs}"
prefix="${RT_PREFIX:-/tmp/rt-prefix}"
cmake_args=()
window_libs=""
if [ -d "$debs" ]; then
  for deb in "$debs"/*.deb; do dpkg-deb -x "$deb" "$prefix"; done
  # Links that name an absolute system path (libz.so -> /lib/.../libz.so.1.2.13) point into
  # the prefix instead.
  find "$prefix" -type l -lname '/*' | while read -r link; do
    ln -sfn "$prefix$(readlink "$link")" "$link"
  done
  export PATH="$prefix/usr/bin:$PATH"
  libs="$prefix/usr/lib/x86_64-linux-gnu"
  libs="$libs:$libs/pulseaudio:$prefix/lib/x86_64-linux-gnu" # Debian 12 still ships some in /lib
  export LD_LIBRARY_PATH="$libs${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
  # Debian keeps some headers in a multiarch folder its compiler searches by default (SDL2's
  # _real_SDL_config.h); in a private prefix the compiler must be told.
  export CPATH="$prefix/usr/include/x86_64-linux-gnu${CPATH:+:$CPATH}"
  cmake_args+=("-DCMAKE_PREFIX_PATH=$prefix/usr")
fi
x11_debs="${RT_X11_DEBS:-$root/.gpu-x11}"
if [ -f "$x11_debs/x11.tar.xz" ] && ! command -v Xvfb >/dev/null; then
  # A virtual X server for the window test, in its own prefix; only the server sees its
  # libraries. Xvfb looks for its GL driver, keyboard data and keyboard compiler at fixed
  # system paths: link them there where this machine has nothing of its own.
  x11="${RT_X11_PREFIX:-/tmp/rt-x11}"
  mkdir -p "$x11/wrap"
  xz -dc "$x11_debs/x11.tar.xz" | tar -C "$x11" -xf -
  x11_libs="$x11/usr/lib/x86_64-linux-gnu:$x11/lib/x86_64-linux-gnu:${LD_LIBRARY_PATH:-}"
  printf '#!/bin/sh\nLD_LIBRARY_PATH="%s" exec "%s" "$@"\n' "$x11_libs" "$x11/usr/bin/Xvfb" \
    >"$x11/wrap/Xvfb"
  chmod +x "$x11/wrap/Xvfb"
  export PATH="$x11/wrap:$PATH"
  # The NVIDIA GLX driver opens X client libraries of its own (such as the GLX protocol
  # library) that a bare CUDA image lacks: the window test finds them after the others.
  window_libs="${LD_LIBRARY_PATH:-}:$x11/usr/lib/x86_64-linux-gnu"
  for path in /usr/lib/x86_64-linux-gnu/dri /usr/share/X11/xkb /usr/bin/xkbcomp; do
    [ -e "$path" ] || { mkdir -p "$(dirname "$path")"; ln -s "$x11$path" "$path"; }
  done
  # NVIDIA's GLX driver gives no visuals unless the vendor-neutral GL dispatch (glvnd) sits in
  # the system's library folder: put it there if the machine has none, and let the private
  # prefix's copies point at it so that one copy is loaded.
  if ! ldconfig -p | grep -q 'libGLX.so.0 '; then
    for pkg in libglvnd0 libgl1 libglx0 libopengl0; do dpkg-deb -x "$debs/${pkg}"_*.deb /; done
    ldconfig
    for lib in "$prefix"/usr/lib/x86_64-linux-gnu/lib{GL,GLX,GLdispatch,OpenGL}.so.*; do
      ln -sf "/usr/lib/x86_64-linux-gnu/$(basename "$lib")" "$lib"
    done
  fi
fi

nvidia-smi >"$logdir/nvidia-smi.txt" 2>&1 || { echo "no NVIDIA GPU answers nvidia-smi"; exit 1; }
gpu=$(nvidia-smi --query-gpu=name --format=csv,noheader | head -1)
echo "GPU: $gpu"

step configure cmake --preset native "${cmake_args[@]}"
# RT_BUILD_TARGETS narrows the build (e.g. "ch09_wide_bvh test_ch09"); narrow the tests with it.
build_targets=()
for target in ${RT_BUILD_TARGETS:-}; do build_targets+=(--target "$target"); done
step build cmake --build --preset native "${build_targets[@]}"
[ $status -eq 0 ] || exit $status
shopt -s nullglob
export RT_SYNC_CHECK=1
# RT_CTEST_ARGS narrows the tests (e.g. "-L ch07").
wanted tests && step tests ctest --preset native --output-junit "$logdir/ctest.xml" ${RT_CTEST_ARGS:-}

if wanted memcheck; then
  for exe in build/native/bin/${RT_MEMCHECK:-ch*}; do # RT_MEMCHECK narrows it (e.g. "ch08*")
    name=$(basename "$exe")
    extra=()
    [ "$name" = ch04_moller_trumbore ] && extra=(--leak-rays 20000)
    [ "$name" = ch05_obj_loading ] && extra=(--scene assets/smooth_torus.obj.gz --scaling-max 2)
    [ "$name" = ch06_lambertian_shading ] && extra=(--skip-cpu)
    [ "$name" = ch07_bvh ] && extra=(--skip-cpu)
    [ "$name" = ch08_texture_memory ] && extra=(--skip-cpu --reference-rays 64)
    [ "$name" = ch09_wide_bvh ] && extra=(--skip-cpu --reference-rays 64)
    [ "$name" = ch10_gpu_build ] && extra=(--skip-cpu)
    [ "$name" = ch11_path_tracing ] && extra=(--spp 2)
    [ "$name" = ch12_materials ] && extra=(--spp 2)
    [ "$name" = ch12_chi2_maps ] && continue # a CPU program
    [ "$name" = ch13_instancing ] && extra=(--small --instances 400 --spin 1 --flat-limit 20000)
    step "memcheck_$name" compute-sanitizer --tool memcheck --leak-check full --error-exitcode 9 \
      "$exe" --backend gpu --width 320 --height 181 --frames 2 "${extra[@]}" \
      --output "$logdir/$name-memcheck.png"
  done
  if [ -x build/native/bin/ch10_gpu_build ]; then # the builds and refits of moving frames
    step memcheck_ch10_moving compute-sanitizer --tool memcheck --leak-check full \
      --error-exitcode 9 build/native/bin/ch10_gpu_build --backend gpu --moving --headless \
      --frames 3 --detail 64 --width 320 --height 181 --output "$logdir/ch10-moving-memcheck.png"
  fi
fi
unset RT_SYNC_CHECK

if wanted reports; then
  for exe in build/native/bin/ch*; do
    name=$(basename "$exe")
    step "report_$name" "$exe" --backend gpu --output "$logdir/$name.png" --json "$logdir/$name.json"
    cat "$logdir/report_$name.log"
  done
fi

have_x=0
command -v Xvfb >/dev/null && have_x=1
window_env=(env __GLX_VENDOR_LIBRARY_NAME=nvidia LD_LIBRARY_PATH="${window_libs:-${LD_LIBRARY_PATH:-}}")
if wanted window; then
  if [ $have_x = 1 ]; then # the chapters' windows, on the GPU's own OpenGL
    step window_test "${window_env[@]}" RT_WINDOW_REPORT=gpu \
      tools/window-test.sh build/native "$logdir/window" interop copy cpu
    grep -v "^wrote" "$logdir/window_test.log" || true
    [ -s "$logdir/window/xvfb.log" ] && tail -20 "$logdir/window/xvfb.log"
  else
    echo "== window_test: skipped, no Xvfb on this machine (the windows are not tested)"
  fi
fi

# Chapter 11 in the window at 1920x1080, one sample per frame: its frame rate on Sponza in
# sunlight and the conference room, and the moving scenes of chapters 10 and 11 in the window
# (the tree rebuilt on the GPU every frame).
if wanted window11 && [ $have_x = 1 ] && [ -x build/native/bin/ch11_path_tracing ]; then
  mkdir -p "$logdir/window11"
  ch11=build/native/bin/ch11_path_tracing
  for scene in sponza-dabrovic:0.3,1,0.2 conference:0.2,1,0.3; do
    name=${scene%%:*}
    [ -f "$models/$name.obj.gz" ] || continue
    step "window_ch11_$name" "${window_env[@]}" tools/window-test.sh --one "$logdir/window11" \
      "$ch11" --window --backend gpu --frames 300 --width 1920 --height 1080 \
      --scene "$models/$name.obj.gz" --sun "${scene#*:}" --sky 0.5 \
      --json "$logdir/window11/window-ch11-$name.json" --output "$logdir/window11/ch11-$name.png"
  done
  step window_ch11_moving "${window_env[@]}" tools/window-test.sh --one "$logdir/window11" \
    "$ch11" --window --backend gpu --moving --frames 300 --width 1920 --height 1080 \
    --json "$logdir/window11/window-ch11-moving.json" --output "$logdir/window11/ch11-moving.png"
  if [ -x build/native/bin/ch10_gpu_build ]; then
    step window_ch10_moving "${window_env[@]}" tools/window-test.sh --one "$logdir/window11" \
      build/native/bin/ch10_gpu_build --window --backend gpu --moving --frames 300 --width 1920 \
      --height 1080 --json "$logdir/window11/window-ch10-moving.json" \
      --output "$logdir/window11/ch10-moving.png"
  fi
  # The same moving scene headless: what a frame costs without the window, tree and sample apart.
  step moving_ch11 "$ch11" --backend gpu --moving --headless --frames 300 --width 1920 \
    --height 1080 --json "$logdir/window11/moving-ch11.json" --output "$logdir/ch11-moving.png"
  if [ -f "$models/stanford-dragon.obj.gz" ]; then # the waving dragon, path-traced
    step moving_ch11_dragon "$ch11" --backend gpu --moving --headless --frames 300 \
      --scene "$models/stanford-dragon.obj.gz" --width 1920 --height 1080 \
      --json "$logdir/window11/moving-ch11-dragon.json" --output "$logdir/ch11-moving-dragon.png"
  fi
  if [ -x build/native/bin/ch13_instancing ]; then # a turning forest of instances
    step window_ch13_forest "${window_env[@]}" tools/window-test.sh --one "$logdir/window11" \
      build/native/bin/ch13_instancing --window --backend gpu --small --instances 10000 --spin 1 \
      --frames 300 --width 1920 --height 1080 --json "$logdir/window11/window-ch13-forest.json" \
      --output "$logdir/window11/ch13-forest.png"
  fi
  if [ -x build/native/bin/ch13_instancing ] && [ -f "$models/stanford-dragon.obj.gz" ]; then
    # 10 000 turning dragons, primary and shadow rays through both levels, in the window
    step window_ch13_dragons "${window_env[@]}" tools/window-test.sh --one "$logdir/window11" \
      build/native/bin/ch13_instancing --window --backend gpu --instances 10000 --spin 0.5 \
      --scene "$models/stanford-dragon.obj.gz" --frames 300 --width 1920 --height 1080 \
      --json "$logdir/window11/window-ch13-dragons.json" \
      --output "$logdir/window11/ch13-dragons.png"
  fi
  grep -h -E "fps|frames|ms" "$logdir"/window_ch1*.log "$logdir"/moving_ch11*.log | head -60
fi

# The real models: every one loads, renders and reports on the GPU, headless; with a virtual X
# server, each also opens the viewer for a few frames of chapter 06.
if wanted models && [ -d "$models" ]; then
  mkdir -p "$logdir/models"
  for model in "$models"/*.obj.gz; do
    name=$(basename "$model" .obj.gz)
    step "model_ch05_$name" build/native/bin/ch05_obj_loading --backend gpu --scene "$model" \
      --width 320 --height 180 --frames 1 --reference-pixels 64 --scaling-max -1 \
      --output "$logdir/models/ch05-$name.png"
    # Chapter 06's report renders a float64 image on the CPU by brute force: the image only.
    step "model_ch06_$name" build/native/bin/ch06_lambertian_shading --backend gpu \
      --scene "$model" --image-only --width 320 --height 180 \
      --output "$logdir/models/ch06-$name.png"
    if [ $have_x = 1 ]; then
      step "model_window_ch06_$name" "${window_env[@]}" tools/window-test.sh build/native \
        "$logdir/models/window-$name" --model "$model"
    fi
  done
  grep -h -E "^ch0|wrote|differ" "$logdir"/model_*.log | head -80
fi
# Chapter 07's benchmark protocol on the benchmark set (kernel-only Mrays/s, build, frame).
if wanted bench && [ -d "$models" ] && [ -x build/native/bin/ch07_bvh ]; then
  step bench build/native/bin/ch07_bvh --backend gpu --benchmark --models "$models" \
    --json "$logdir/bench.json"
  cat "$logdir/bench.log"
fi
if wanted bench08 && [ -d "$models" ] && [ -x build/native/bin/ch08_texture_memory ]; then
  step bench_ch08 build/native/bin/ch08_texture_memory --backend gpu --benchmark \
    --models "$models" --json "$logdir/bench_ch08.json"
  cat "$logdir/bench_ch08.log"
fi
if wanted bench09 && [ -d "$models" ] && [ -x build/native/bin/ch09_wide_bvh ]; then
  step bench_ch09 build/native/bin/ch09_wide_bvh --backend gpu --benchmark \
    --models "$models" --json "$logdir/bench_ch09.json"
  cat "$logdir/bench_ch09.log"
fi
if wanted bench10 && [ -x build/native/bin/ch10_gpu_build ]; then
  if [ -d "$models" ]; then
    step bench_ch10 build/native/bin/ch10_gpu_build --backend gpu --benchmark \
      --models "$models" --json "$logdir/bench_ch10.json"
    cat "$logdir/bench_ch10.log"
  fi
  step moving_ch10 build/native/bin/ch10_gpu_build --backend gpu --moving --headless \
    --frames 300 --animation-csv "$logdir/ch10_animation.csv" --json "$logdir/moving_ch10.json" \
    --output "$logdir/ch10_moving.png"
  tail -8 "$logdir/moving_ch10.log"
  if [ -f "$models/stanford-dragon.obj.gz" ]; then # the 871k-triangle dragon, waving
    step moving_ch10_dragon build/native/bin/ch10_gpu_build --backend gpu --moving --headless \
      --scene "$models/stanford-dragon.obj.gz" --frames 300 \
      --animation-csv "$logdir/ch10_animation_dragon.csv" --json "$logdir/moving_ch10_dragon.json" \
      --output "$logdir/ch10_moving_dragon.png"
    tail -8 "$logdir/moving_ch10_dragon.log"
  fi
fi
# Chapter 11 at 1920x1080: each kernel's time per sample, rays per path and Mrays/s (against
# chapter 09's diffuse rays), on the Cornell room, Sponza in sunlight and the conference room
# under a sky (both from the benchmark's interior views); then the convergence reports behind
# the book's plots, and what the profiler counts in the megakernel and the persistent threads.
if wanted bench12 && [ -x build/native/bin/ch12_materials ]; then
  ch12=build/native/bin/ch12_materials
  step bench_ch12_room "$ch12" --backend gpu --headless --width 1920 --height 1080 \
    --frames 50 --spp 64 --json "$logdir/bench_ch12_room.json" --output "$logdir/ch12_room.png"
  step convergence_ch12_room "$ch12" --backend gpu --headless --convergence --width 320 \
    --height 240 --spp 1024 --reference-spp 16384 --json "$logdir/convergence_ch12_room.json"
  cat "$logdir"/bench_ch12_*.log
fi
if wanted bench13 && [ -x build/native/bin/ch13_instancing ]; then
  ch13=build/native/bin/ch13_instancing
  # Each top level and walk named in RT_CH13_TOPS (binary nested wide; default: all three).
  for top in ${RT_CH13_TOPS:-binary nested wide}; do
    args=(--backend gpu --headless --width 1920 --height 1080 --top "$top")
    if [ -f "$models/stanford-dragon.obj.gz" ]; then
      # 10 000 dragons (8.7 billion triangles as placed), still and turning; 16 of them against
      # the same scene flattened into one tree.
      step "bench_ch13_forest_$top" "$ch13" "${args[@]}" --scene "$models/stanford-dragon.obj.gz" \
        --instances 10000 --spin 0.5 --flat-limit 0 --json "$logdir/bench_ch13_forest_$top.json" \
        --output "$logdir/ch13_forest_$top.png"
      step "bench_ch13_flat_$top" "$ch13" "${args[@]}" --scene "$models/stanford-dragon.obj.gz" \
        --instances 16 --flat-limit 20000000 --json "$logdir/bench_ch13_flat_$top.json" --output ""
    fi
    # A million instances of a 320-triangle sphere: the top level's build.
    step "bench_ch13_million_$top" "$ch13" "${args[@]}" --small --instances 1000000 --spin 0.5 \
      --flat-limit 0 --json "$logdir/bench_ch13_million_$top.json" \
      --output "$logdir/ch13_million_$top.png"
  done
  cat "$logdir"/bench_ch13_*.log
fi
if wanted bench11 && [ -x build/native/bin/ch11_path_tracing ]; then
  ch11=build/native/bin/ch11_path_tracing
  step bench_ch11_room "$ch11" --backend gpu --headless --width 1920 --height 1080 \
    --frames 50 --json "$logdir/bench_ch11_room.json" --output "$logdir/ch11_room.png"
  if [ -f "$models/sponza-dabrovic.obj.gz" ]; then
    step bench_ch11_sponza "$ch11" --backend gpu --headless --scene \
      "$models/sponza-dabrovic.obj.gz" --sun 0.3,1,0.2 --sky 0.5 --width 1920 --height 1080 \
      --frames 50 --json "$logdir/bench_ch11_sponza.json" --output "$logdir/ch11_sponza.png"
    step convergence_ch11_sponza "$ch11" --backend gpu --headless --convergence --scene \
      "$models/sponza-dabrovic.obj.gz" --sun 0.3,1,0.2 --sky 0.5 --width 320 --height 240 \
      --spp 1024 --reference-spp 16384 --json "$logdir/convergence_ch11_sponza.json"
  fi
  if [ -f "$models/conference.obj.gz" ]; then
    step bench_ch11_conference "$ch11" --backend gpu --headless --scene \
      "$models/conference.obj.gz" --sun 0.2,1,0.3 --sky 0.5 --width 1920 --height 1080 \
      --frames 50 --json "$logdir/bench_ch11_conference.json" \
      --output "$logdir/ch11_conference.png"
    step convergence_ch11_conference "$ch11" --backend gpu --headless --convergence --scene \
      "$models/conference.obj.gz" --sun 0.2,1,0.3 --sky 0.5 --width 320 --height 240 \
      --spp 1024 --reference-spp 16384 --json "$logdir/convergence_ch11_conference.json"
  fi
  step convergence_ch11_room "$ch11" --backend gpu --headless --convergence --width 320 \
    --height 240 --spp 1024 --reference-spp 65536 --json "$logdir/convergence_ch11_room.json"
  cat "$logdir"/bench_ch11_*.log
  if command -v ncu >/dev/null && [ -f "$models/sponza-dabrovic.obj.gz" ]; then
    metrics=gpu__time_duration.sum,smsp__thread_inst_executed_per_inst_executed.ratio
    metrics=$metrics,sm__warps_active.avg.pct_of_peak_sustained_active,smsp__inst_executed.sum
    metrics=$metrics,l1tex__t_sector_hit_rate.pct,sm__throughput.avg.pct_of_peak_sustained_elapsed
    metrics=$metrics,launch__registers_per_thread,launch__grid_size
    for variant in megakernel persistent; do # one sample of Sponza at 1920x1080, the image only
      step "profile_ch11_$variant" ncu --kernel-name-base demangled --kernel-name \
        regex:"MegakernelPixel<rt::ch06::Spec|persistent_paths_kernel<rt::ch06::Spec" \
        --launch-count 1 --csv --metrics "$metrics" "$ch11" --backend gpu --headless \
        --scene "$models/sponza-dabrovic.obj.gz" --sun 0.3,1,0.2 --sky 0.5 --width 1920 \
        --height 1080 --image-only --spp 1 --variant $variant --output "$logdir/ch11_$variant.png"
    done
  fi
fi
# Chapter 11's samplers: error against run time by sampler (each point a fresh image of that
# many samples) on the three scenes at 640x360 against a 16384-sample reference, and each
# sampler's kernels timed at 1920x1080 (the headless report, 50 frames); chapter 12's material
# room by sampler too.
if wanted samplers && [ -x build/native/bin/ch11_path_tracing ]; then
  ch11=build/native/bin/ch11_path_tracing
  for scene in room sponza-dabrovic:0.3,1,0.2 conference:0.2,1,0.3; do
    name=${scene%%:*}
    args=()
    if [ "$name" != room ]; then
      [ -f "$models/$name.obj.gz" ] || continue
      args=(--scene "$models/$name.obj.gz" --sun "${scene#*:}" --sky 0.5)
    fi
    step "samplers_ch11_$name" "$ch11" --backend gpu --headless --convergence --samplers \
      "${args[@]}" --width 640 --height 360 --spp 256 --reference-spp 16384 \
      --json "$logdir/samplers_ch11_$name.json"
    grep -h "sampler " "$logdir/samplers_ch11_$name.log"
    for sampler in independent stratified sobol zsobol; do
      step "sampler_time_ch11_${name}_$sampler" "$ch11" --backend gpu --headless "${args[@]}" \
        --sampler $sampler --width 1920 --height 1080 --frames 50 --spp 64 \
        --json "$logdir/sampler_time_ch11_${name}_$sampler.json" \
        --output "$logdir/ch11_${name}_$sampler.png"
      grep -h "persistent\|megakernel\|wavefront" "$logdir/sampler_time_ch11_${name}_$sampler.log"
    done
  done
  if [ -x build/native/bin/ch12_materials ]; then
    step samplers_ch12_room build/native/bin/ch12_materials --backend gpu --headless \
      --convergence --samplers --width 320 --height 240 --spp 256 --reference-spp 16384 \
      --json "$logdir/samplers_ch12_room.json"
    grep -h "sampler " "$logdir/samplers_ch12_room.log"
  fi
fi
# Chapter 08's kernels as the GPU runs them: load instructions per kernel, and cache hit rates.
if wanted sass && [ -x build/native/bin/ch08_texture_memory ]; then
  step sass tools/sass-loads.py build/native/bin/ch08_texture_memory
  cat "$logdir/sass.log"
fi
if wanted profile && [ -x build/native/bin/ch08_texture_memory ]; then
  if command -v ncu >/dev/null; then
    scene="$models/${RT_PROFILE_SCENE:-conference}.obj.gz"
    [ -f "$scene" ] || scene=assets/torus_knot_100k.obj.gz
    step profile tools/profile-paths.sh build/native/bin/ch08_texture_memory "$scene" \
      "$logdir/profile.csv"
    cat "$logdir/profile.log"
  else
    echo "== profile: skipped, no ncu on this machine"
  fi
fi
grep -h -E "tests passed|tests failed" "$logdir/tests.log" 2>/dev/null
exit $status
