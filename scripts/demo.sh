#!/usr/bin/env bash
# First command of the README: install dependencies, build tinbase in Release, and run
# `tinbase demo` on the bundled data (an embedded SQLite store; no server to start).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cmake -S . -B build/release -G Ninja -DCMAKE_BUILD_TYPE=Release -DTINBASE_BUILD_TESTS=OFF >/dev/null
cmake --build build/release --target tinbase -j "$(nproc)"
scripts/build-web.sh   # the web viewer of `tinbase serve` (web/dist)
build/release/apps/tinbase demo --workdir "${TINBASE_DEMO_DIR:-build/demo}"
