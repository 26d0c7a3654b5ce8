#!/usr/bin/env bash
# Builds every chapter and runs every test this machine can run:
#   tools/test.sh [preset]      (default preset: default; also native, debug, sanitize)
# On a machine without an NVIDIA GPU the tests labelled gpu are left out, and it says so.
set -euo pipefail
cd "$(dirname "$0")/.."
preset="${1:-default}"
tools/install-deps.sh
source tools/env.sh
cmake --preset "$preset"
cmake --build --preset "$preset"
if nvidia-smi -L >/dev/null 2>&1; then
  ctest --preset "$preset"
else
  skipped=$(ctest --test-dir "build/$preset" -N -L gpu | sed -n 's/^Total Tests: //p')
  echo "No NVIDIA GPU here: leaving out the $skipped tests labelled gpu (they run on a GPU machine)."
  ctest --preset "$preset" -LE gpu
fi
