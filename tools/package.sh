#!/usr/bin/env bash
# Writes the portable release (docs/release.md) in two parts that unpack into one folder:
#   OUT/style4d-VERSION-linux-x86_64.tar.gz        bin/style4d (shaders embedded) and lib/ with every
#                                                  library it needs that is not glibc's
#                                                  (tools/release/system-libs.txt), the Vulkan loader
#                                                  among them;
#   OUT/style4d-VERSION-linux-x86_64-video.tar.gz  lib/libs4d_video.so, the video plugin, and the
#                                                  libraries only it needs (OpenCV's videoio, FFmpeg).
# RUNPATHs are rewritten to $ORIGIN-relative ones, so the folder runs from anywhere. --checks adds
# what tools/gpu-check.sh runs (docs/gpu.md): the benches, the GPU test executables (bin/tests), the
# validation layer and the check itself, for a GPU machine that has no build (the folder and
# tarballs are then named ...-checks). --sizes prints what each part costs. Prints the two tarballs'
# paths last, the program's part first.
# Usage: tools/package.sh [--build DIR] [--out DIR] [--checks] [--sizes]   (defaults: build, dist; needs patchelf)
set -euo pipefail
usage() { echo "usage: tools/package.sh [--build DIR] [--out DIR] [--checks] [--sizes]" >&2; exit 2; }
root=$(cd "$(dirname "$0")/.." && pwd)
build=$root/build out=$root/dist checks=0 sizes=0
while [ $# -gt 0 ]; do
  case "$1" in
    --build) [ $# -ge 2 ] || usage; build=$(realpath "$2"); shift 2 ;;
    --out) [ $# -ge 2 ] || usage; mkdir -p "$2"; out=$(realpath "$2"); shift 2 ;;
    --checks) checks=1; shift ;;
    --sizes) sizes=1; shift ;;
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
cp "$root/docs/release.md" "$dir/README.md"
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

# Every library they load, by soname, as this system resolves them; glibc's stay out. What only
# the video plugin needs goes with it into the video part.
mapfile -t system < <(grep -v '^#' "$root/tools/release/system-libs.txt")
is_system() { local s; for s in "${system[@]}"; do [ "$1" = "$s" ] && return 0; done; return 1; }
needs() { ldd "$@" | awk '$2 == "=>" { print $1, $3 }' | sort -u; }
video_files=("lib/libs4d_video.so")
copy() {  # PART SONAME PATH
  is_system "$2" && return 0
  [ -f "$3" ] || { echo "tools/package.sh: $2 is not found on this system (ldd)" >&2; exit 1; }
  [ -f "$dir/lib/$2" ] && return 0
  cp -L "$3" "$dir/lib/$2"
  [ "$1" = video ] && video_files+=("lib/$2")
  return 0
}
while read -r soname path; do copy core "$soname" "$path"; done < <(needs "${programs[@]}")
while read -r soname path; do copy video "$soname" "$path"; done < <(needs "$dir/lib/libs4d_video.so")
# Each library finds its neighbours; each program finds lib/ (the video plugin by name too).
for p in "${programs[@]}"; do
  patchelf --set-rpath "\$ORIGIN/$(realpath --relative-to="$(dirname "$p")" "$dir/lib")" "$p"
done
for f in "$dir"/lib/*; do patchelf --set-rpath '$ORIGIN' "$f"; done

mkdir -p "$out"
core_tar=$out/$name.tar.gz video_tar=$out/$name-video.tar.gz
printf "$name/%s\n" "${video_files[@]}" > "$stage/video.list"
tar -C "$stage" -czf "$core_tar" --exclude-from="$stage/video.list" "$name"
tar -C "$stage" -czf "$video_tar" -T "$stage/video.list"

if [ "$sizes" = 1 ]; then
  gz() { gzip -c "$@" | wc -c; }
  row() { printf '%-40s %6s %11s %11s\n' "$@"; }
  files() { tar -tzf "$1" | grep -vc '/$'; }
  row part files bytes "tar.gz"
  row "style4d alone (program and shaders)" 1 "$(stat -c %s "$dir/bin/style4d")" "$(gz "$dir/bin/style4d")"
  row "program part: $(basename "$core_tar")" "$(files "$core_tar")" "$(($(du -sb "$dir" | cut -f1) - $(cd "$stage" && cat $(cat video.list) | wc -c)))" "$(stat -c %s "$core_tar")"
  row "video part: $(basename "$video_tar")" "$(files "$video_tar")" "$(cd "$stage" && cat $(cat video.list) | wc -c)" "$(stat -c %s "$video_tar")"
  echo "the 15 largest libraries, each gzipped alone (bytes):"
  for f in "$dir"/lib/*; do printf '%11s  %s\n' "$(gz "$f")" "$(basename "$f")"; done | sort -rn | head -15
fi
echo "$core_tar"
echo "$video_tar"
