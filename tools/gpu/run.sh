#!/usr/bin/env bash
# The GPU-machine run: on any Linux machine with an NVIDIA GPU, builds the course for that GPU,
# runs every test (the [gpu] ones too), runs compute-sanitizer's memcheck on each chapter
# executable and runs each chapter's report (its benchmark), writing logs to a folder.
#
#   tools/gpu/run.sh [LOGDIR]           (default LOGDIR: gpu-logs)
#
# Offline machines: run tools/gpu/fetch-debs.sh where there is internet, copy .gpu-debs/ along;
# this script unpacks it into a private prefix (RT_PREFIX, default /tmp/rt-prefix).
set -uo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
cd "$root"
logdir="$(realpath -m "${1:-gpu-logs}")"
mkdir -p "$logdir"
source tools/env.sh
status=0
step() { # step NAME COMMAND...: runs a command, logs it, remembers a failure
  local name=$1; shift
  echo "== $name: $*"
  if "$@" >"$logdir/$name.log" 2>&1; then echo "   ok"; else echo "   FAILED (see $name.log)"; tail -30 "$logdir/$name.log"; status=1; fi
}

debs="${RT_DEBS:-$root/.gpu-debs}"
prefix="${RT_PREFIX:-/tmp/rt-prefix}"
cmake_args=()
if [ -d "$debs" ]; then
  for deb in "$debs"/*.deb; do dpkg-deb -x "$deb" "$prefix"; done
  export PATH="$prefix/usr/bin:$PATH"
  libs="$prefix/usr/lib/x86_64-linux-gnu"
  libs="$libs:$libs/pulseaudio:$prefix/lib/x86_64-linux-gnu" # Debian 12 still ships some in /lib
  export LD_LIBRARY_PATH="$libs${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
  # Debian keeps some headers in a multiarch folder its compiler searches by default (SDL2's
  # _real_SDL_config.h); in a private prefix the compiler must be told.
  export CPATH="$prefix/usr/include/x86_64-linux-gnu${CPATH:+:$CPATH}"
  cmake_args+=("-DCMAKE_PREFIX_PATH=$prefix/usr")
fi

nvidia-smi >"$logdir/nvidia-smi.txt" 2>&1 || { echo "no NVIDIA GPU answers nvidia-smi"; exit 1; }
gpu=$(nvidia-smi --query-gpu=name --format=csv,noheader | head -1)
echo "GPU: $gpu"

step configure cmake --preset native "${cmake_args[@]}"
step build cmake --build --preset native
[ $status -eq 0 ] || exit $status
shopt -s nullglob
export RT_SYNC_CHECK=1
step tests ctest --preset native --output-junit "$logdir/ctest.xml"

for exe in build/native/bin/ch*; do
  name=$(basename "$exe")
  step "memcheck_$name" compute-sanitizer --tool memcheck --leak-check full --error-exitcode 9 \
    "$exe" --backend gpu --width 320 --height 181 --frames 2 --output "$logdir/$name-memcheck.png"
done
unset RT_SYNC_CHECK

for exe in build/native/bin/ch*; do
  name=$(basename "$exe")
  step "report_$name" "$exe" --backend gpu --output "$logdir/$name.png" --json "$logdir/$name.json"
  cat "$logdir/report_$name.log"
done
if command -v Xvfb >/dev/null; then # chapter 02's window, on the GPU's own OpenGL
  step window_test env __GLX_VENDOR_LIBRARY_NAME=nvidia tools/window-test.sh build/native \
    "$logdir/window" interop copy cpu
  cat "$logdir/window_test.log" | grep "window-test:"
else
  echo "== window_test: skipped, no Xvfb on this machine (chapter 02's window is not tested)"
fi
grep -h -E "tests passed|tests failed" "$logdir/tests.log"
exit $status
