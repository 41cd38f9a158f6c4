#!/usr/bin/env bash
# Fresh Debian 12 -> set up, build, and run the whole test suite on lavapipe (Mesa's CPU Vulkan
# driver) with the Vulkan validation layer on; any validation error fails its test.
# Set S4D_TEST_DEVICE=any to run on the machine's default device instead of lavapipe.
set -euo pipefail
cd "$(dirname "$0")/.."
# Test-only packages: a single-node Slurm for the sweep's Slurm back end (tests/sweep/slurm_cluster.sh);
# clang-14 with its sanitizer runtimes and libFuzzer for the readers' fuzz smoke run (tests/fuzz/build_and_smoke.sh);
# PyTorch for the learned metrics' references and the weight converter's test (tests/metrics_nn/torch_reference.py);
# Chromium for the browser tests of the study page and report.html (tests/browser, with node and npm).
test_packages=(slurm-wlm munge clang-14 libclang-rt-14-dev libfuzzer-14-dev python3-torch python3-torchvision chromium)
missing=()
for p in "${test_packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "[run-tests] installing: ${missing[*]}" >&2
  sudo_cmd=()
  [ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
  export DEBIAN_FRONTEND=noninteractive
  "${sudo_cmd[@]}" apt-get update -qq
  "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
tools/setup.sh
# The browser tests' npm packages (puppeteer-core, pinned by tests/browser/package-lock.json).
if command -v npm >/dev/null; then
  (cd tests/browser && npm ci --no-audit --no-fund --loglevel=error)
else
  echo "[run-tests] npm not found: the browser tests will be skipped" >&2
fi
build_dir="${S4D_BUILD_DIR:-build}"
if [ "${S4D_TEST_DEVICE:-lavapipe}" = "lavapipe" ]; then
  icd=$(ls /usr/share/vulkan/icd.d/lvp_icd.*.json 2>/dev/null | head -1)
  [ -n "$icd" ] || { echo "lavapipe ICD not found (apt-get install mesa-vulkan-drivers)" >&2; exit 1; }
  export VK_ICD_FILENAMES="$icd" VK_DRIVER_FILES="$icd"
fi
export S4D_VALIDATION=1
ctest --test-dir "$build_dir" --output-on-failure --parallel "$(nproc)" --timeout 900
