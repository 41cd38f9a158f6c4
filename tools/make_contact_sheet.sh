#!/usr/bin/env bash
# Builds s4d_contact_sheet and writes docs/stylizer_contact_sheet.png: the default (patch) stylizer
# on every content picture x style picture of a data folder with content/ and styles/ (photographs
# and paintings whose licences allow it). The product itself never needs this data.
#   tools/make_contact_sheet.sh DATA_DIR [BUILD_DIR]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
if [ $# -lt 1 ] || [ ! -d "$1/content" ] || [ ! -d "$1/styles" ]; then
  echo "usage: tools/make_contact_sheet.sh DATA_DIR [BUILD_DIR]: DATA_DIR needs content/ and styles/ folders" >&2
  exit 2
fi
data="$1"
build="${2:-$root/build}"
cmake --build "$build" --target s4d_contact_sheet -j2
mkdir -p "$root/docs"
"$build/s4d_contact_sheet" --content "$data/content" --styles "$data/styles" \
  --out "$root/docs/stylizer_contact_sheet.png" --work 256 --cell 160
