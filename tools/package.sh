#!/usr/bin/env bash
# Writes the portable release, OUT/style4d-VERSION-linux-x86_64.tar.gz (docs/release.md): bin/style4d
# with its shaders embedded, lib/ with the video plugin and every library they need that is not
# glibc's (tools/release/system-libs.txt), the Vulkan loader among them. RUNPATHs are rewritten to
# $ORIGIN-relative ones, so the folder runs from anywhere. --checks adds what tools/gpu-check.sh
# runs (docs/gpu.md): the benches, the GPU test executables (bin/tests), the validation layer and
# the check itself, for a GPU machine that has no build. Prints a table of what each part costs
# compressed, then the tarball's path last.
# Usage: tools/package.sh [--build DIR] [--out DIR] [--checks]   (defaults: build, dist; needs patchelf)
set -euo pipefail
usage() { echo "usage: tools/package.sh [--build DIR] [--out DIR] [--checks]" >&2; exit 2; }
root=$(cd "$(dirname "$0")/.." && pwd)
build=$root/build out=$root/dist checks=0
while [ $# -gt 0 ]; do
  case "$1" in
    --build) [ $# -ge 2 ] || usage; build=$(realpath "$2"); shift 2 ;;
    --out) [ $# -ge 2 ] || usage; mkdir -p "$2"; out=$(realpath "$2"); shift 2 ;;
    --checks) checks=1; shift ;;
    *) echo "tools/package.sh: unknown argument '$1'" >&2; usage ;;
  esac
done
command -v patchelf >/dev/null || { echo "tools/package.sh: patchelf is missing (apt-get install patchelf)" >&2; exit 1; }
need() {
  [ -f "$build/$1" ] || { echo "tools/package.sh: $build/$1 is missing: build it first (cmake --build $build --target ${2:-style4d})" >&2; exit 1; }
}
need style4d
need libs4d_video.so

# The project's version (CMakeLists.txt), with the commit when the tree is a git checkout.
version=$(sed -n 's/^project(style4d VERSION \([0-9.]*\).*/\1/p' "$root/CMakeLists.txt")
commit=$(git -C "$root" rev-parse --short HEAD 2>/dev/null || true)
[ -n "$commit" ] && version="$version+g$commit"
name=style4d-$version-linux-x86_64
[ "$checks" = 1 ] && name=$name-checks
stage=$(mktemp -d)
trap 'rm -rf "$stage"' EXIT
dir=$stage/$name
mkdir -p "$dir/bin" "$dir/lib"
cp "$build/style4d" "$dir/bin/"
cp "$build/libs4d_video.so" "$dir/lib/"
programs=("$dir/bin/style4d")
if [ "$checks" = 1 ]; then
  for b in s4d_bench_splat s4d_bench_viewer s4d_bench_deform; do need "$b" "$b"; cp "$build/$b" "$dir/bin/"; programs+=("$dir/bin/$b"); done
  mkdir -p "$dir/bin/tests" "$dir/tools" "$dir/share/vulkan/explicit_layer.d"
  for t in "$build"/tests/test_gpu_*; do [ -x "$t" ] && cp "$t" "$dir/bin/tests/" && programs+=("$dir/bin/tests/$(basename "$t")"); done
  cp "$root/tools/gpu-check.sh" "$root/tools/gpu_check_report.py" "$dir/tools/"
  # The validation layer, found through VK_LAYER_PATH (gpu-check.sh sets it); its manifest names
  # the library relative to itself.
  layer=/usr/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json
  [ -f "$layer" ] || { echo "tools/package.sh: --checks needs the validation layer (apt-get install vulkan-validationlayers)" >&2; exit 1; }
  layer_lib=$(sed -n 's/.*"library_path" *: *"\([^"]*\)".*/\1/p' "$layer")
  cp -L "$(ldconfig -p | awk -v n="$layer_lib" '$1 == n { print $NF; exit }')" "$dir/lib/$layer_lib"
  sed "s|\"library_path\" *: *\"[^\"]*\"|\"library_path\": \"../../../lib/$layer_lib\"|" "$layer" > "$dir/share/vulkan/explicit_layer.d/$(basename "$layer")"
fi
strip --strip-unneeded "${programs[@]}" "$dir/lib/libs4d_video.so"

# Every library they load, by soname, as this system resolves them; glibc's stay out.
mapfile -t system < <(grep -v '^#' "$root/tools/release/system-libs.txt")
is_system() { local s; for s in "${system[@]}"; do [ "$1" = "$s" ] && return 0; done; return 1; }
while read -r soname path; do
  is_system "$soname" && continue
  [ -f "$path" ] || { echo "tools/package.sh: $soname is not found on this system (ldd)" >&2; exit 1; }
  [ -f "$dir/lib/$soname" ] || cp -L "$path" "$dir/lib/$soname"
done < <(ldd "${programs[@]}" "$dir/lib/libs4d_video.so" | awk '$2 == "=>" { print $1, $3 }' | sort -u)
# Each library finds its neighbours; each program finds lib/ (the video plugin by name too).
for p in "${programs[@]}"; do
  rel=$(realpath --relative-to="$(dirname "$p")" "$dir/lib")
  patchelf --set-rpath "\$ORIGIN/$rel" "$p"
done
for f in "$dir"/lib/*; do patchelf --set-rpath '$ORIGIN' "$f"; done
cp "$root/docs/release.md" "$dir/README.md"

mkdir -p "$out"
tarball=$out/$name.tar.gz
tar -C "$stage" -czf "$tarball" "$name"

# What each part costs: bytes, and gzip-compressed bytes of the part alone.
gz() { gzip -c "$@" | wc -c; }
row() { printf '%-36s %6s %10s %10s\n' "$@"; }
mapfile -t core < <(ldd "$dir/bin/style4d" | awk '$2 == "=>" { print $1 }' | sort -u)
core_files=("$dir/bin/style4d")
for b in "${core[@]}"; do [ -f "$dir/lib/$b" ] && core_files+=("$dir/lib/$b"); done
mapfile -t video < <(cd "$dir/lib" && ldd libs4d_video.so | awk '$2 == "=>" { print $1 }' | sort -u)
video_files=("$dir/lib/libs4d_video.so")
for b in "${video[@]}"; do
  printf '%s\n' "${core[@]}" | grep -qx "$b" || { [ -f "$dir/lib/$b" ] && video_files+=("$dir/lib/$b"); }
done
row part files bytes gzipped
row "style4d (program and shaders)" 1 "$(stat -c %s "$dir/bin/style4d")" "$(gz "$dir/bin/style4d")"
row "core: style4d and its libraries" "${#core_files[@]}" "$(cat "${core_files[@]}" | wc -c)" "$(cat "${core_files[@]}" | gz)"
row "video plugin and its own libraries" "${#video_files[@]}" "$(cat "${video_files[@]}" | wc -c)" "$(cat "${video_files[@]}" | gz)"
if [ "$checks" = 1 ]; then
  extra=("$dir"/bin/s4d_bench_* "$dir"/bin/tests/* "$dir/lib/$layer_lib")
  row "checks: benches, GPU tests, layer" "${#extra[@]}" "$(cat "${extra[@]}" | wc -c)" "$(cat "${extra[@]}" | gz)"
fi
echo "the 12 largest libraries, gzipped bytes:"
for f in "$dir"/lib/*; do printf '%10s  %s\n' "$(gz "$f")" "$(basename "$f")"; done | sort -rn | head -12
row "bundle (tar.gz)" "$(find "$dir" -type f | wc -l)" "$(du -sb "$dir" | cut -f1)" "$(stat -c %s "$tarball")"
echo "$tarball"
