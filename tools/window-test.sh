#!/usr/bin/env bash
# Runs chapters 02 to 11 in a real window and checks each screenshot against the
# headless output of the same frame, pixel for pixel (same pixels give byte-identical PNGs).
#   tools/window-test.sh BUILD_DIR OUT_DIR [PATH...]    (paths: interop copy cpu; default cpu)
#   tools/window-test.sh BUILD_DIR OUT_DIR --model FILE  (a model file in the viewers of the
#                                                        shading chapters, on the GPU)
# With RT_WINDOW_REPORT=gpu (or cpu) it also runs the window report of every path at the
# default size, for the book's table.
# Without a DISPLAY it starts a virtual X server (Xvfb) for the run.
#   tools/window-test.sh --one OUT_DIR COMMAND...        (runs one command in the X server)
set -euo pipefail
one=0
if [ "$1" = --one ]; then
  one=1; out="$2"; shift 2
else
  build="$1"; out="$2"; shift 2
fi
mkdir -p "$out"
xvfb_pid=""
if [ -z "${DISPLAY:-}" ]; then
  display=":$((90 + RANDOM % 9))"
  Xvfb "$display" -screen 0 1920x1080x24 +extension GLX -nolisten tcp >"$out/xvfb.log" 2>&1 &
  xvfb_pid=$!
  trap 'kill $xvfb_pid 2>/dev/null || true' EXIT
  export DISPLAY="$display"
  for _ in $(seq 50); do [ -e "/tmp/.X11-unix/X${display#:}" ] && break; sleep 0.1; done
fi
if [ $one = 1 ]; then
  "$@"
  exit
fi
paths=("${@:-cpu}")
exe="$build/bin/ch02_pbo_interop"
frames=60
backend=cpu
status=0
compare() { # compare NAME WINDOW_PNG HEADLESS_PNG
  if cmp -s "$2" "$3"; then
    echo "window-test: $1: screenshot identical to the headless frame"
  else
    echo "window-test: $1: screenshot DIFFERS from the headless frame"; status=1
  fi
}
if [ "${1:-}" = --model ]; then
  model="$2"
  name=$(basename "$model" .obj.gz)
  for chapter in ch06_lambertian_shading ch07_bvh ch08_texture_memory ch09_wide_bvh \
    ch10_gpu_build ch11_path_tracing; do
    [ -x "$build/bin/$chapter" ] || continue
    extra=()
    [ "$chapter" = ch11_path_tracing ] && extra=(--spp 5) # the window's 5 frames: 5 samples
    "$build/bin/$chapter" --window --backend gpu --frames 5 --width 320 --height 181 \
      --scene "$model" --output "$out/window-$chapter-$name.png" --json "$out/window-$chapter-$name.json"
    "$build/bin/$chapter" --headless --backend gpu --image-only --width 320 --height 181 \
      --scene "$model" "${extra[@]}" --output "$out/headless-$chapter-$name.png" >/dev/null
    compare "$chapter $name" "$out/window-$chapter-$name.png" "$out/headless-$chapter-$name.png"
  done
  exit $status
fi
for path in "${paths[@]}"; do
  [ "$path" = cpu ] && backend=cpu || backend=gpu
  "$exe" --window --backend "$backend" --path "$path" --frames $frames --width 320 --height 181 \
    --output "$out/window-$path.png" --json "$out/window-$path.json"
  "$exe" --headless --backend "$backend" --frames $frames --width 320 --height 181 \
    --output "$out/headless-$path.png"
  compare "ch02 $path" "$out/window-$path.png" "$out/headless-$path.png"
  # Chapters 03 and 04 open the interactive viewer: interop on the GPU, upload on the CPU.
  [ "$path" = copy ] && continue
  for chapter in ch03_spheres ch04_moller_trumbore ch05_obj_loading ch06_lambertian_shading \
    ch07_bvh ch08_texture_memory ch09_wide_bvh ch10_gpu_build ch11_path_tracing; do
    [ -x "$build/bin/$chapter" ] || continue
    extra=()
    scene=()
    [ "$chapter" = ch04_moller_trumbore ] && extra=(--leak-rays 1000)
    [ "$chapter" = ch06_lambertian_shading ] && extra=(--image-only)
    [ "$chapter" = ch07_bvh ] && extra=(--image-only)
    [ "$chapter" = ch08_texture_memory ] && extra=(--image-only)
    [ "$chapter" = ch09_wide_bvh ] && extra=(--image-only)
    [ "$chapter" = ch10_gpu_build ] && extra=(--image-only)
    # A frame in the window adds a sample: the headless image of 10 samples is its twin.
    [ "$chapter" = ch11_path_tracing ] && extra=(--image-only --spp 10)
    if [ "$chapter" = ch05_obj_loading ]; then # the small room: brute force on 100k is slow
      scene=(--scene "$(dirname "$0")/../assets/cornell_room.obj.gz")
      extra=(--scaling-max -1)
    fi
    "$build/bin/$chapter" --window --backend "$backend" --frames 10 --width 320 --height 181 \
      "${scene[@]}" --output "$out/window-$chapter-$path.png" \
      --json "$out/window-$chapter-$path.json"
    "$build/bin/$chapter" --headless --backend "$backend" --frames 1 --width 320 --height 181 \
      "${scene[@]}" "${extra[@]}" --output "$out/headless-$chapter-$path.png" >/dev/null
    compare "$chapter $path" "$out/window-$chapter-$path.png" \
      "$out/headless-$chapter-$path.png"
  done
done
if [ -n "${RT_WINDOW_REPORT:-}" ]; then # the chapter's window report at its default size
  "$exe" --window --backend "$RT_WINDOW_REPORT" --path all --frames 120 \
    --json "$out/window-report.json" \
    --output "$out/window-report.png"
  for chapter in ch03_spheres ch04_moller_trumbore ch05_obj_loading; do
    [ -x "$build/bin/$chapter" ] || continue
    [ "$chapter" = ch05_obj_loading ] && [ "$RT_WINDOW_REPORT" = cpu ] && continue
    "$build/bin/$chapter" --window --backend "$RT_WINDOW_REPORT" --frames 120 \
      --json "$out/window-report-$chapter.json" --output "$out/window-report-$chapter.png"
  done
fi
exit $status
