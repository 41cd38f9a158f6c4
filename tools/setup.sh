#!/usr/bin/env bash
# Sets up a fresh Debian 12 machine for style4d and builds it: installs the missing Debian
# packages (with sudo when not root), configures and builds into build/ (override with
# S4D_BUILD_DIR). Safe to re-run: installs only what is missing, rebuilds only what changed.
# Usage: tools/setup.sh [TARGET...]   (default: every target, the tests included)
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(
  build-essential cmake ninja-build pkg-config
  libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers vulkan-tools
  glslc spirv-tools
  libglm-dev nlohmann-json3-dev doctest-dev libpng-dev libjpeg-dev libopenexr-dev libopencv-dev
  libglfw3-dev libimgui-dev xvfb xauth
  patchelf  # tools/package.sh
  libcpp-httplib-dev libsqlite3-dev
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "[setup] installing: ${missing[*]}" >&2
  sudo_cmd=()
  [ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
  export DEBIAN_FRONTEND=noninteractive
  "${sudo_cmd[@]}" apt-get update -qq
  "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

build_dir="${S4D_BUILD_DIR:-build}"
preset_flags=(-DCMAKE_BUILD_TYPE=Release)
[ "${CI:-}" = "true" ] && preset_flags+=(-DS4D_WERROR=ON)
cmake -S . -B "$build_dir" -G Ninja "${preset_flags[@]}" >/dev/null
if [ $# -gt 0 ]; then
  cmake --build "$build_dir" --parallel "$(nproc)" --target "$@"
else
  cmake --build "$build_dir" --parallel "$(nproc)"
fi
