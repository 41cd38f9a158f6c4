#!/usr/bin/env bash
# ctest's entry to the browser tests: they need node, Debian's chromium and the npm packages of
# package-lock.json (tools/run-tests.sh installs all three); without them the test is skipped (77),
# saying what is missing.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
missing=()
command -v node >/dev/null || missing+=("node")
[ -x "${CHROMIUM:-/usr/bin/chromium}" ] || missing+=("chromium (apt-get install chromium)")
[ -d "$here/node_modules/puppeteer-core" ] || missing+=("puppeteer-core (cd tests/browser && npm ci)")
if [ ${#missing[@]} -gt 0 ]; then
  echo "browser tests skipped: missing ${missing[*]}"
  exit 77
fi
mkdir -p "$S4D_BROWSER_WORK"
exec node --test --test-concurrency=1 "$@"
