#!/usr/bin/env bash
# Writes the portable release, OUT/style4d-VERSION-linux-x86_64.tar.gz (docs/release.md): bin/style4d
# with its shaders embedded, lib/ with the video plugin and every library the two need that is not
# glibc's (tools/release/system-libs.txt), the Vulkan loader among them. RUNPATHs are rewritten to
# $ORIGIN-relative ones, so the folder runs from anywhere. Prints the tarball's path last, after a
# table of what each part costs compressed.
# Usage: tools/package.sh [--build DIR] [--out DIR]   (defaults: build, dist; needs patchelf)
set -euo pipefail
usage() { echo "usage: tools/package.sh [--build DIR] [--out DIR]" >&2; exit 2; }
root=$(cd "$(dirname "$0")/.." && pwd)
build=$root/build out=$root/dist
while [ $# -gt 0 ]; do
  case "$1" in
    --build) [ $# -ge 2 ] || usage; build=$(realpath "$2"); shift 2 ;;
    --out) [ $# -ge 2 ] || usage; mkdir -p "$2"; out=$(realpath "$2"); shift 2 ;;
    *) echo "tools/package.sh: unknown argument '$1'" >&2; usage ;;
  esac
done
command -v patchelf >/dev/null || { echo "tools/package.sh: patchelf is missing (apt-get install patchelf)" >&2; exit 1; }
for f in style4d libs4d_video.so; do
  [ -f "$build/$f" ] || { echo "tools/package.sh: $build/$f is missing: build it first (cmake --build $build --target style4d)" >&2; exit 1; }
done

# The project's version (CMakeLists.txt), with the commit when the tree is a git checkout.
version=$(sed -n 's/^project(style4d VERSION \([0-9.]*\).*/\1/p' "$root/CMakeLists.txt")
commit=$(git -C "$root" rev-parse --short HEAD 2>/dev/null || true)
[ -n "$commit" ] && version="$version+g$commit"
name=style4d-$version-linux-x86_64
stage=$(mktemp -d)
trap 'rm -rf "$stage"' EXIT
dir=$stage/$name
mkdir -p "$dir/bin" "$dir/lib"
cp "$build/style4d" "$dir/bin/"
cp "$build/libs4d_video.so" "$dir/lib/"
strip --strip-unneeded "$dir/bin/style4d" "$dir/lib/libs4d_video.so"

# Every library the two load, by soname, as this system resolves them; glibc's stay out.
mapfile -t system < <(grep -v '^#' "$root/tools/release/system-libs.txt")
is_system() { local s; for s in "${system[@]}"; do [ "$1" = "$s" ] && return 0; done; return 1; }
while read -r soname path; do
  is_system "$soname" && continue
  [ -f "$path" ] || { echo "tools/package.sh: $soname is not found on this system (ldd)" >&2; exit 1; }
  cp -L "$path" "$dir/lib/$soname"
done < <(ldd "$dir/bin/style4d" "$dir/lib/libs4d_video.so" | awk '$2 == "=>" { print $1, $3 }' | sort -u)
# Each library finds its neighbours; the program finds lib/ (the video plugin by name too).
patchelf --set-rpath '$ORIGIN/../lib' "$dir/bin/style4d"
for f in "$dir"/lib/*; do patchelf --set-rpath '$ORIGIN' "$f"; done
cp "$root/docs/release.md" "$dir/README.md"

mkdir -p "$out"
tarball=$out/$name.tar.gz
tar -C "$stage" -czf "$tarball" "$name"

# What each part costs: its bytes alone, gzip-compressed (the tarball compresses them together).
gz() { gzip -c "$@" | wc -c; }
core=(); video=()
mapfile -t core < <(ldd "$dir/bin/style4d" | awk '$2 == "=>" { print $1 }' | sort -u)
for f in "$dir"/lib/*; do
  b=$(basename "$f")
  printf '%s\n' "${core[@]}" | grep -qx "$b" || video+=("$f")
done
core_files=("$dir/bin/style4d")
for b in "${core[@]}"; do [ -f "$dir/lib/$b" ] && core_files+=("$dir/lib/$b"); done
printf '%-34s %6s %10s %10s\n' part files bytes gzipped
printf '%-34s %6s %10s %10s\n' "style4d (program, shaders)" 1 "$(stat -c %s "$dir/bin/style4d")" "$(gz "$dir/bin/style4d")"
printf '%-34s %6s %10s %10s\n' "core: program + its libraries" "${#core_files[@]}" "$(cat "${core_files[@]}" | wc -c)" "$(cat "${core_files[@]}" | gzip -c | wc -c)"
printf '%-34s %6s %10s %10s\n' "video plugin + its libraries" "${#video[@]}" "$(cat "${video[@]}" | wc -c)" "$(cat "${video[@]}" | gzip -c | wc -c)"
echo "the 12 largest libraries, gzipped bytes:"
for f in "$dir"/lib/*; do printf '%10s  %s\n' "$(gz "$f")" "$(basename "$f")"; done | sort -rn | head -12
printf '%-34s %6s %10s %10s\n' "bundle (tar.gz)" "$(find "$dir" -type f | wc -l)" "$(du -sb "$dir" | cut -f1)" "$(stat -c %s "$tarball")"
echo "$tarball"
