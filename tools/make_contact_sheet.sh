#!/usr/bin/env bash
# Builds s4d_contact_sheet and writes docs/stylizer_contact_sheet.png: the default (patch) stylizer
# on every content picture x style picture of a data folder (default /work/shared/data, with
# content/ and styles/; see its SOURCES.md files). The product itself never needs this data.
#   tools/make_contact_sheet.sh [DATA_DIR] [BUILD_DIR]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
data="${1:-/work/shared/data}"
build="${2:-$root/build}"
cmake --build "$build" --target s4d_contact_sheet -j2
mkdir -p "$root/docs"
"$build/s4d_contact_sheet" --content "$data/content" --styles "$data/styles" \
  --out "$root/docs/stylizer_contact_sheet.png" --work 256 --cell 160
