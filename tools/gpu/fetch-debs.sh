#!/usr/bin/env bash
# Downloads the Debian packages of tools/gpu/debs.txt into a folder (default: .gpu-debs), for
# a GPU machine without internet. Copy the folder over; tools/gpu/run.sh unpacks it into a
# private prefix there (nothing is installed system-wide).
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
dest="$(realpath -m "${1:-$root/.gpu-debs}")"
mkdir -p "$dest"
mapfile -t packages < <(grep -v '^#' "$root/tools/gpu/debs.txt" | grep -v '^[[:space:]]*$')
lists=$(mktemp -d)
trap 'rm -rf "$lists"' EXIT
opts=(-o APT::Architecture=amd64 -o APT::Architectures=amd64 -o Dir::State::Lists="$lists")
mkdir -p "$lists/partial"
apt-get "${opts[@]}" update -q >/dev/null
(cd "$dest" && apt-get "${opts[@]}" download "${packages[@]}")
echo "downloaded ${#packages[@]} packages into $dest"
