#!/usr/bin/env bash
# The full crash loop (docs/reliability.md, "kill -9"): 1000 SIGKILLs of the CLI's writing
# commands, each followed by `check --full` and the all-or-none checks of
# tests/stress/crash_loop_test.cc (the test command runs 50 of them).
#   tests/stress/crash_loop.sh [BUILD_DIR] [KILLS] [SEED]
# BUILD_DIR defaults to build/test (configured with -DTINBASE_BUILD_TESTS=ON); SEED replays a run.
# The rounds run a copy of the tinbase binary, so that a rebuild meanwhile does not disturb them.
set -euo pipefail
build=${1:-build/test}
kills=${2:-1000}
binary="$build/tests/crash_loop_test"
if [[ ! -x "$binary" ]]; then
  echo "crash_loop.sh: $binary is missing: ninja -C $build crash_loop_test tinbase" >&2
  exit 1
fi
export TINBASE_CRASH_KILLS="$kills"
copy=$(mktemp -d)
trap 'rm -rf "$copy"' EXIT
cp "$build/apps/tinbase" "$copy/tinbase"
cp "$binary" "$copy/crash_loop_test"
export TINBASE_CRASH_CLI="$copy/tinbase"
if [[ $# -ge 3 ]]; then export TINBASE_CRASH_SEED="$3"; fi
"$copy/crash_loop_test" --gtest_brief=1
