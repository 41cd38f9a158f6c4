#!/usr/bin/env bash
# Fresh Debian 12 -> set up, build, and run the main job on the built-in scene and style.
# Usage: tools/run-demo.sh [OUT_DIR]   (default: out/demo)
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup.sh style4d  # the program only: the tests' build is not the demo's
exec "${S4D_BUILD_DIR:-build}/style4d" demo --out "${1:-out/demo}"
