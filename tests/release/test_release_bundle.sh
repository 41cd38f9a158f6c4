#!/usr/bin/env bash
# The release in a clean environment (docs/release.md): tools/package.sh writes the bundle (the
# program's part and the video part), both are unpacked into an empty folder and run under `env -i`
# with only VK_ICD_FILENAMES (the Vulkan driver), HOME and TMPDIR set: devices, synth (videos, so the
# video plugin loads), a few train steps, render, make-style, a few stylize steps and bench. A run
# that touches no video (devices) loads nothing of the video part. Every library each run loaded,
# as the dynamic loader logs it (LD_DEBUG), must be
#   - in the bundle, or
#   - glibc's or the dynamic loader (tools/release/system-libs.txt), or
#   - the ICD's library (library_path in the VK_ICD_FILENAMES file), a system implicit Vulkan layer's,
#     or one they need (their ldd closure).
# Usage: test_release_bundle.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1 src=$2
icd=${VK_ICD_FILENAMES:?the release test needs VK_ICD_FILENAMES naming the Vulkan driver (lavapipe in CI)}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

mapfile -t tarballs < <("$src/tools/package.sh" --build "$build" --out "$work/dist" | tail -2)
mkdir "$work/unpacked" "$work/home" "$work/tmp" "$work/ld"
for t in "${tarballs[@]}"; do tar -C "$work/unpacked" -xzf "$t"; done  # the program's part, then the video part
bundle=$(echo "$work"/unpacked/style4d-*)
[ -x "$bundle/bin/style4d" ] || { echo "FAIL: no bin/style4d in ${tarballs[0]}"; exit 1; }

# Runs the unpacked program under env -i; the loader's log goes to ld/NAME.PID.
step() {
  local name=$1; shift
  if ! env -i VK_ICD_FILENAMES="$icd" HOME="$work/home" TMPDIR="$work/tmp" LD_DEBUG=files,libs \
      LD_DEBUG_OUTPUT="$work/ld/$name" "$bundle/bin/style4d" "$@" > "$work/$name.log" 2>&1; then
    echo "FAIL: style4d $* exited non-zero:"; cat "$work/$name.log"; exit 1
  fi
}
step devices devices
step synth synth --out "$work/data" --cams 3 --frames 2 --size 32x24 --video
step train train --data "$work/data" --out "$work/run" --preset fast --iters 20 --fine-iters 4 --batch 1 --skip-check
step render render --run "$work/run" --out "$work/render" --path spiral --frames 2
step make_style make-style --out "$work/style.png" --size 32
step stylize stylize --run "$work/run" --style "$work/style.png" --name s --iters 4 --mlp-iters 2 --spiral-frames 2
step bench bench --run "$work/run" --style s --spiral-frames 2 --out "$work/bench"
[ -f "$work/bench/report.json" ] || { echo "FAIL: bench wrote no report.json"; exit 1; }

# The libraries the system may provide: the ICD's library and its closure, the implicit Vulkan
# layers the system installs (the loader loads them for every Vulkan program, e.g. Mesa's device
# select layer) and theirs, glibc's.
vulkan_lib() {  # the library_path of a Vulkan manifest, made absolute
  local lib
  lib=$(sed -n 's/.*"library_path" *: *"\([^"]*\)".*/\1/p' "$1")
  case "$lib" in /*) ;; */*) lib=$(dirname "$1")/$lib ;; *) lib=$(ldconfig -p | awk -v n="$lib" '$1 == n { print $NF; exit }') ;; esac
  echo "$lib"
}
{
  for manifest in "$icd" /usr/share/vulkan/implicit_layer.d/*.json /etc/vulkan/implicit_layer.d/*.json; do
    [ -f "$manifest" ] || continue
    lib=$(vulkan_lib "$manifest")
    [ -n "$lib" ] && [ -e "$lib" ] || continue
    realpath "$lib"
    ldd "$lib" | awk '$2 == "=>" { print $3 }' | xargs -r realpath
  done
} | sort -u > "$work/icd_libs"
grep -v '^#' "$src/tools/release/system-libs.txt" > "$work/glibc_names"

# Each loaded library's path: the file named when its link map is made, or else the last file the
# loader tried for it (its RUNPATH, the cache and the default folders are all logged as tries).
loaded() {
  awk '
    /trying file=/ { sub(/.*trying file=/, ""); tried = $0; next }
    /generating link map/ { sub(/.*file=/, ""); sub(/ \[[0-9]+\];.*/, ""); print (substr($0, 1, 1) == "/" ? $0 : tried) }
  ' "$@" | xargs -r realpath | sort -u
}
loaded "$work"/ld/* > "$work/loaded"
tar -tzf "${tarballs[1]}" | grep -v '/$' | sed "s|^|$work/unpacked/|" | xargs -r realpath | sort > "$work/video_part"
without_video=$(loaded "$work"/ld/devices.* | comm -12 - "$work/video_part")
[ -z "$without_video" ] || { echo "FAIL: style4d devices loaded the video part: $without_video"; exit 1; }
bundle_real=$(realpath "$bundle")
fail=0 from_bundle=0 from_system=0 bytes=0
while read -r lib; do
  bytes=$((bytes + $(stat -c %s "$lib")))
  if [[ $lib == "$bundle_real"/* ]]; then from_bundle=$((from_bundle + 1)); continue; fi
  from_system=$((from_system + 1))
  grep -qxF "$lib" "$work/icd_libs" && continue
  grep -qxF "$(basename "$lib")" "$work/glibc_names" && continue
  echo "FAIL: loaded from the system, outside the allowed list: $lib"; fail=1
done < "$work/loaded"
[ "$from_bundle" -gt 10 ] || { echo "FAIL: only $from_bundle libraries came from the bundle (the log was not read?)"; fail=1; }
grep -q "/lib/libs4d_video.so$" "$work/loaded" || { echo "FAIL: the video plugin never loaded (synth --video writes videos)"; fail=1; }
echo "loaded $((from_bundle + from_system)) libraries, $((bytes / 1048576)) MiB: $from_bundle from the bundle, $from_system from the system"
exit $fail
