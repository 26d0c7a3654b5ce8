#!/usr/bin/env bash
# Copies models into .gpu-models/ as plain files, so that they travel to a GPU machine with the
# checkout (models/ may hold only links to copies elsewhere; tools/gpu/run.sh reads either).
#   tools/gpu/pack-models.sh [NAME...]   (names without .obj.gz; default: the benchmark set)
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
from="${RT_MODELS_FROM:-$root/models}"
dest="$root/.gpu-models"
names=("${@:-stanford-bunny armadillo-100k stanford-dragon conference sponza-dabrovic}")
read -r -a names <<<"${names[*]}"
rm -rf "$dest"
mkdir -p "$dest"
for name in "${names[@]}"; do
  cp "$from/$name.obj.gz" "$dest/"
  [ -f "$from/$name.mtl" ] && cp "$from/$name.mtl" "$dest/"
done
echo "packed ${#names[@]} models into $dest ($(du -sh "$dest" | cut -f1))"
