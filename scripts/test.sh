#!/usr/bin/env bash
# Second command of the README (and what .ci/run calls): install dependencies and the npm test
# tools (scripts/install-test-tools.sh: the glTF validator), build everything
# with warnings as errors, run the whole test suite with CTest, then the style checks
# (scripts/lint.sh: clang-format and clang-tidy). The PostgreSQL tests get a throwaway server
# (scripts/pg-server.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/install-test-tools.sh
scripts/build-web.sh --browser-tests   # the viewer and its browser tests' npm packages
cmake -S . -B build/test -G Ninja -DCMAKE_BUILD_TYPE=Release -DTINBASE_BUILD_TESTS=ON \
  -DTINBASE_WERROR=ON -DTINBASE_BUILD_BENCH=ON >/dev/null
cmake --build build/test -j "$(nproc)"
# The PostgreSQL backend's tests run against a throwaway server on loopback, stopped at the end.
pg_dir=$(mktemp -d /tmp/tinbase-pg.XXXXXX)
trap 'scripts/pg-server.sh stop "$pg_dir"' EXIT
TINBASE_TEST_POSTGRES_URL=$(scripts/pg-server.sh start "$pg_dir")
export TINBASE_TEST_POSTGRES_URL
(cd build/test && ctest --output-on-failure -j "$(nproc)" --timeout 900)
# The parsers' libFuzzer targets (fuzz/), built with clang, about 30 s of fuzzing each.
cmake -S . -B build/fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_C_COMPILER=clang -DTINBASE_FUZZ=ON -DTINBASE_BUILD_TESTS=OFF >/dev/null
cmake --build build/fuzz -j "$(nproc)" --target fuzz_targets
(cd build/fuzz && ctest --output-on-failure -R '^fuzz_')
scripts/lint.sh all build/test
