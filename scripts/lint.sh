#!/usr/bin/env bash
# Style checks that CI runs (scripts/test.sh calls this after the tests; also `ninja lint`):
#   format  clang-format --dry-run -Werror (.clang-format: Google, 100 columns) over every *.cc
#           and *.h in core/ db/ service/ apps/ extensions/ tests/ bench/ fuzz/;
#   tidy    clang-tidy with the checks of .clang-tidy (warnings are errors) over every translation
#           unit of those folders in BUILD_DIR/compile_commands.json, and the headers they include
#           from those folders.
# Usage: scripts/lint.sh [format|tidy|all] [BUILD_DIR]   (default: all, build/test)
# BUILD_DIR needs only CMake's configure step (the one generated header is written then).
# Exit status: 0 when both are clean; 1 naming the unformatted files or printing the findings.
# LINT_JOBS sets clang-tidy's parallelism (default: nproc). CLANG_FORMAT and CLANG_TIDY name the
# binaries (default: clang-format and clang-tidy from PATH; Debian 12 ships version 14).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
what=${1:-all}
build=${2:-build/test}
clang_format=${CLANG_FORMAT:-clang-format}
clang_tidy=${CLANG_TIDY:-clang-tidy}
jobs=${LINT_JOBS:-$(nproc)}
dirs=(core db service apps extensions tests bench fuzz)

case "$what" in
  format | tidy | all) ;;
  *) echo "usage: scripts/lint.sh [format|tidy|all] [BUILD_DIR]" >&2; exit 2 ;;
esac

# The sources: tracked files in a clone, every file otherwise (a tarball, a copy).
sources() {
  if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
    git ls-files -- "${dirs[@]/%//*.cc}" "${dirs[@]/%//*.h}"
  else
    find "${dirs[@]}" -type f \( -name '*.cc' -o -name '*.h' \) | sort
  fi
}

status=0

if [ "$what" != tidy ]; then
  start=$SECONDS
  unformatted=()
  while IFS= read -r f; do
    "$clang_format" --dry-run -Werror "$f" >/dev/null 2>&1 || unformatted+=("$f")
  done < <(sources)
  total=$(sources | wc -l)
  if [ ${#unformatted[@]} -gt 0 ]; then
    printf 'lint: not clang-format clean (fix with: %s -i FILE):\n' "$clang_format"
    printf '  %s\n' "${unformatted[@]}"
    status=1
  fi
  echo "lint: format: ${#unformatted[@]} of $total files unclean ($((SECONDS - start)) s)"
fi

if [ "$what" != format ]; then
  start=$SECONDS
  db="$build/compile_commands.json"
  [ -f "$db" ] || { echo "lint: no $db (configure with CMake first)" >&2; exit 2; }
  # CMake writes one `"file": "/abs/path",` line per translation unit.
  pattern="^$root/($(IFS='|'; echo "${dirs[*]}"))/"
  mapfile -t units < <(sed -n 's/^ *"file": "\(.*\)",\{0,1\}$/\1/p' "$db" | grep -E "$pattern" |
    sort -u)
  [ ${#units[@]} -gt 0 ] || { echo "lint: no sources of ${dirs[*]} in $db" >&2; exit 2; }
  log=$(mktemp)
  trap 'rm -f "$log"' EXIT
  # One file per clang-tidy run, so a slow one does not hold back a batch; the findings of a
  # header included by several units are printed once below.
  printf '%s\n' "${units[@]}" |
    xargs -P "$jobs" -n 1 "$clang_tidy" -p "$build" --quiet --header-filter="$pattern" \
      >"$log" 2>&1 || true
  findings=$(grep -E '^/.*:[0-9]+:[0-9]+: (warning|error): ' "$log" | sort -u || true)
  count=$(printf '%s' "$findings" | grep -c . || true)
  if [ "$count" -gt 0 ]; then
    echo "lint: clang-tidy findings:"
    printf '%s\n' "$findings" | sed "s|^$root/||"
    status=1
  elif grep -qE '(error|Error)' "$log"; then
    cat "$log"
    status=1
  fi
  echo "lint: tidy: $count findings in ${#units[@]} translation units ($((SECONDS - start)) s)"
fi

exit $status
