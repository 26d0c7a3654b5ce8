#!/usr/bin/env bash
# Installs the Debian/Ubuntu packages in tools/deps.txt (skips what is already installed) and
# checks that the CUDA toolkit's nvcc can be found. Used by the README, tools/test.sh and CI.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
mapfile -t packages < <(grep -v '^#' "$here/deps.txt" | grep -v '^[[:space:]]*$')

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "installing: ${missing[*]}"
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -q
  $sudo apt-get install -y -q --no-install-recommends "${missing[@]}"
fi

if ! command -v nvcc >/dev/null && [ ! -x /usr/local/cuda/bin/nvcc ]; then
  echo "error: the CUDA toolkit (nvcc) was not found; install it from NVIDIA's CUDA downloads" \
       "page and put its bin folder on PATH (usually /usr/local/cuda/bin)" >&2
  exit 1
fi
