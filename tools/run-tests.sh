#!/usr/bin/env bash
# Fresh Debian 12 -> set up, build, and run the whole test suite on lavapipe (Mesa's CPU Vulkan
# driver) with the Vulkan validation layer on; any validation error fails its test.
# Set S4D_TEST_DEVICE=any to run on the machine's default device instead of lavapipe.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup.sh
build_dir="${S4D_BUILD_DIR:-build}"
if [ "${S4D_TEST_DEVICE:-lavapipe}" = "lavapipe" ]; then
  icd=$(ls /usr/share/vulkan/icd.d/lvp_icd.*.json 2>/dev/null | head -1)
  [ -n "$icd" ] || { echo "lavapipe ICD not found (apt-get install mesa-vulkan-drivers)" >&2; exit 1; }
  export VK_ICD_FILENAMES="$icd" VK_DRIVER_FILES="$icd"
fi
export S4D_VALIDATION=1
ctest --test-dir "$build_dir" --output-on-failure --parallel "$(nproc)" --timeout 900
