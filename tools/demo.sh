#!/usr/bin/env bash
# Builds the course's most advanced chapter and runs it on its default scene: writes an image
# to out/ and prints the error-against-run-time report. Extra arguments go to the chapter.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install-deps.sh
source tools/env.sh
cmake --preset default >/dev/null
cmake --build --preset default --target latest
latest=$(sed -n 's/^RT_LATEST_CHAPTER:INTERNAL=//p' build/default/CMakeCache.txt)
mkdir -p out
exec "build/default/bin/$latest" --output "out/$latest.png" "$@"
