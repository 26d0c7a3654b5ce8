#!/usr/bin/env bash
# Downloads what an offline GPU machine needs into two folders (default: .gpu-debs and
# .gpu-x11), to be copied over; tools/gpu/run.sh unpacks them there into private prefixes
# (nothing is installed system-wide):
#   - .gpu-debs: the Debian packages of tools/gpu/debs.txt (build dependencies, libraries);
#   - .gpu-x11/x11.tar.xz: the packages of tools/gpu/x11-debs.txt (a virtual X server with
#     GLX for the window test), unpacked here and packed again without documentation, in one
#     archive small enough to travel. Rebuilt only when that list or this script changes (xz -9 takes a few minutes).
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
dest="$(realpath -m "${1:-$root/.gpu-debs}")"
x11_dest="$(realpath -m "${2:-$root/.gpu-x11}")"
mkdir -p "$dest" "$x11_dest"
package_list() { grep -v '^#' "$1" | grep -v '^[[:space:]]*$'; }
lists=$(mktemp -d)
work=$(mktemp -d)
trap 'rm -rf "$lists" "$work"' EXIT
opts=(-o APT::Architecture=amd64 -o APT::Architectures=amd64 -o Dir::State::Lists="$lists")
mkdir -p "$lists/partial"
apt-get "${opts[@]}" update -q >/dev/null

mapfile -t packages < <(package_list "$root/tools/gpu/debs.txt")
(cd "$dest" && apt-get "${opts[@]}" download "${packages[@]}")
echo "downloaded ${#packages[@]} packages into $dest"

x11_list="$root/tools/gpu/x11-debs.txt"
stamp="$(cat "$x11_list" "$0" | sha256sum | cut -d' ' -f1)"
if [ -f "$x11_dest/x11.tar.xz" ] && [ "$(cat "$x11_dest/x11.stamp" 2>/dev/null)" = "$stamp" ]; then
  echo "x11.tar.xz is up to date"
  exit 0
fi
mapfile -t x11_packages < <(package_list "$x11_list")
mkdir -p "$work/debs" "$work/root"
(cd "$work/debs" && apt-get "${opts[@]}" download "${x11_packages[@]}")
for deb in "$work"/debs/*.deb; do dpkg-deb -x "$deb" "$work/root"; done
rm -rf "$work"/root/usr/share/{doc,man,locale,lintian,bug} "$work/root/usr/include"
# ICU comes in only because LLVM (Mesa's software renderer) links libxml2, which links ICU's
# common library; nothing on the server's path calls it. Its 31 MB data library becomes a stub
# that defines the one symbol the common library needs, and ICU's other libraries go, so that
# the archive, the build's packages and two interior models travel together (64 MiB limit).
lib="$work/root/usr/lib/x86_64-linux-gnu"
rm -f "$lib"/libicu{i18n,io,test,tu}.so*
data=$(basename "$lib"/libicudata.so.*.*)
version=${data#libicudata.so.}
version=${version%%.*}
printf 'const char icudt%s_dat[32] = {0};\n' "$version" |
  cc -shared -fPIC -x c - -Wl,-soname,"libicudata.so.$version" -o "$lib/$data"
tar -C "$work/root" -cf - . | xz -9 -T0 >"$x11_dest/x11.tar.xz"
echo "$stamp" >"$x11_dest/x11.stamp"
echo "packed ${#x11_packages[@]} packages into $x11_dest/x11.tar.xz ($(du -h "$x11_dest/x11.tar.xz" | cut -f1))"
