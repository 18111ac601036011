#!/usr/bin/env bash
# Builds the web viewer into web/dist (what `tinbase serve` serves by default): installs the npm
# packages exactly as web/package-lock.json pins them (CesiumJS), then copies the page
# (web/src) and Cesium's built files next to it, so the page needs no CDN and no network at run
# time. With --browser-tests it also installs the browser tests' packages (tests/browser:
# playwright-core, which drives Debian's chromium and downloads no browser).
# Idempotent: `npm ci` is skipped while a tree matches its lock file.
# Usage: scripts/build-web.sh [--browser-tests]
set -euo pipefail
cd "$(dirname "$0")/.."

for tool in node npm; do
  command -v "$tool" >/dev/null || {
    echo "build-web: '$tool' is not installed (scripts/install-deps.sh installs it)" >&2
    exit 1
  }
done

# `npm ci` in $1 unless node_modules was installed from the same lock file (a stamp holds its hash).
install_locked() {
  local dir=$1
  local stamp="$dir/node_modules/.tinbase-lock.sha256"
  local want
  want=$(sha256sum "$dir/package-lock.json" | cut -d' ' -f1)
  if [ -f "$stamp" ] && [ "$(cat "$stamp")" = "$want" ]; then
    echo "build-web: $dir/node_modules is up to date"
    return
  fi
  (cd "$dir" && npm ci --no-audit --no-fund --loglevel=error)
  echo "$want" >"$stamp"
}

install_locked web
# Cesium's index.js is one ES module; it loads its workers, assets and wasm from CESIUM_BASE_URL.
cesium=web/node_modules/cesium/Build/Cesium
rm -rf web/dist.tmp
mkdir -p web/dist.tmp/cesium
cp -R "$cesium/index.js" "$cesium/Assets" "$cesium/ThirdParty" "$cesium/Widgets" \
  "$cesium/Workers" web/dist.tmp/cesium/
cp -R web/src/. web/dist.tmp/
rm -rf web/dist
mv web/dist.tmp web/dist
echo "build-web: web/dist holds the viewer with cesium $(node -p \
  "require('./web/node_modules/cesium/package.json').version")"

if [ "${1:-}" = "--browser-tests" ]; then
  install_locked tests/browser
fi
