#!/usr/bin/env bash
# Installs the npm tools tinbase's tests use to check outputs with readers we did not write
# (today the Khronos glTF-Validator, npm gltf-validator) into tests/tools/node_modules, exactly as
# tests/tools/package-lock.json pins them. Idempotent: does nothing when the installed tree
# already matches the lock file. Needs node and npm (Debian: nodejs, npm).
# Usage: scripts/install-test-tools.sh
set -euo pipefail
cd "$(dirname "$0")/../tests/tools"

for tool in node npm; do
  command -v "$tool" >/dev/null || {
    echo "install-test-tools: '$tool' is not installed (scripts/install-deps.sh installs it)" >&2
    exit 1
  }
done

# A stamp holds the hash of the lock file the tree was installed from; while it matches, `npm ci`
# (which deletes node_modules and reinstalls from the registry) is skipped.
stamp=node_modules/.tinbase-lock.sha256
want=$(sha256sum package-lock.json | cut -d' ' -f1)
if [ -f "$stamp" ] && [ "$(cat "$stamp")" = "$want" ] && [ -d node_modules/gltf-validator ]; then
  echo "install-test-tools: tests/tools/node_modules is up to date"
  exit 0
fi
npm ci --no-audit --no-fund --loglevel=error
echo "$want" >"$stamp"
echo "install-test-tools: installed $(node -p "require('gltf-validator/package.json').version" \
  2>/dev/null || echo '?') gltf-validator into tests/tools/node_modules"
