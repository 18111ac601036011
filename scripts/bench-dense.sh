#!/usr/bin/env bash
# Issue 30's benchmark: dense TINs on rough terrain. `tinbase tin build` (store write and commit
# included) against fogleman/hmm (STL written) and npm delatin, each a whole process timed with
# /usr/bin/time (wall time and peak RSS), alternated within each row, every mesh scored on every
# cell by bench/dense_bench.cc. The terrain: fBm with Hurst exponent 1, 0-2000 m, + 0.3 m white
# noise, 30 m cells, quantised to the 16 bits hmm reads (bench/generated_terrain.h RoughTerrain).
#
# Usage: scripts/bench-dense.sh HMM_BINARY [OUTDIR] [SIZES] [ERRORS] [REPEATS]
#        scripts/bench-dense.sh --table RESULTS.csv   (the table of an earlier run)
#   defaults: build-bench/dense, "2049 4097", "0.5 1 5 20", 1.
# HMM_BINARY: hmm built from source with its own Makefile flags, e.g.
#   apt-get install libglm-dev
#   git clone https://github.com/fogleman/hmm /tmp/hmm && make -C /tmp/hmm   # -> /tmp/hmm/hmm
# Needs node + npm (delatin from bench/peers). Writes OUTDIR/results.csv and prints a table.
set -euo pipefail

# The table of a results.csv: one row per size and error, each tool's best time, tinbase's ratios
# to hmm.
table() {
  echo "| grid | max error | tinbase s (triangles, true max) | hmm s (triangles, true max) | delatin s | tinbase / hmm wall | tinbase / hmm CPU | tinbase / hmm peak RSS | tinbase / hmm triangles at hmm's true error |"
  echo "|---|---|---|---|---|---|---|---|---|"
  awk -F, 'NR > 1 {
    key = $1 "," $2
    if (!(key in seen)) { seen[key] = 1; keys[++n] = key }
    if (!((key, $4) in best) || $5 < best[key, $4]) best[key, $4] = $5
    if (!((key, $4) in cpu) || $10 < cpu[key, $4]) cpu[key, $4] = $10
    rss[key, $4] = $6; tri[key, $4] = $7; err[key, $4] = $8
    if ($4 == "hmm") same[key] = $9
  } END {
    for (i = 1; i <= n; i++) {
      k = keys[i]; split(k, p, ",")
      printf "| %s^2 | %s m | %.2f (%d, %.3f) | %.2f (%d, %.3f) | %.2f | %.2fx | %.2fx | %.2fx | %.3fx |\n",
        p[1], p[2], best[k, "tinbase"], tri[k, "tinbase"], err[k, "tinbase"],
        best[k, "hmm"], tri[k, "hmm"], err[k, "hmm"], best[k, "delatin"],
        best[k, "tinbase"] / best[k, "hmm"], cpu[k, "tinbase"] / cpu[k, "hmm"],
      rss[k, "tinbase"] / rss[k, "hmm"],
        same[k] / tri[k, "hmm"]
    }
  }' "$1"
}
if [ "${1:-}" = "--table" ]; then table "$2"; exit 0; fi
cd "$(dirname "$0")/.."
hmm=${1:?usage: scripts/bench-dense.sh HMM_BINARY [OUTDIR] [SIZES] [ERRORS] [REPEATS]}
out=${2:-build-bench/dense}
sizes=${3:-2049 4097}
errors=${4:-0.5 1 5 20}
repeats=${5:-1}
build=${TINBASE_BENCH_BUILD:-build-bench}
[ -x "$hmm" ] || { echo "hmm binary '$hmm' not found or not executable (see the usage)"; exit 1; }
[ -x /usr/bin/time ] || { echo "/usr/bin/time is missing (apt-get install time)"; exit 1; }
mkdir -p "$out"
(cd bench/peers && npm ci --no-audit --no-fund --silent)
if [ -z "${TINBASE_BENCH_BUILD:-}" ]; then
  cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DTINBASE_BUILD_BENCH=ON >/dev/null
  ninja -C "$build" tinbase dense_bench >/dev/null
fi
tinbase=$build/apps/tinbase
bench=$build/bench/dense_bench

# Runs a command under /usr/bin/time; prints "wall_seconds peak_rss_kib cpu_seconds" (user +
# system: on a machine shared with other work, the fairer of the two times).
timed() {
  /usr/bin/time -f '%e %M %U %S' -o "$out/time.txt" "$@" >"$out/last.log" 2>&1 ||
    { cat "$out/last.log"; exit 1; }
  awk '{ printf "%s %s %.2f\n", $1, $2, $3 + $4 }' "$out/time.txt"
}

csv=$out/results.csv
echo "size,error,repeat,tool,seconds,peak_rss_mib,triangles,true_max_error,tinbase_at_same_error,cpu_seconds" >"$csv"
for n in $sizes; do
  dir=$out/rough-$n
  "$bench" export --size "$n" --out "$dir"
  zscale=$(sed 's/.*"zscale":\([0-9.e+-]*\).*/\1/' "$dir/terrain.json")
  rm -f "$dir/base.tinbase"*
  "$tinbase" init "$dir/base.tinbase" >/dev/null
  "$tinbase" --quiet dem import "$dir/base.tinbase" "$dir/terrain.tif" >/dev/null
  for e in $errors; do
    for rep in $(seq 1 "$repeats"); do
      # A different order each repeat, so no tool always runs first after the previous row.
      order=("hmm tinbase delatin" "tinbase delatin hmm" "delatin hmm tinbase")
      for tool in ${order[$(( (rep - 1) % 3 ))]}; do
        case $tool in
          hmm)
            he=$(awk -v e="$e" -v z="$zscale" 'BEGIN { printf "%.9g", e / z }')
            read -r s k cpu < <(timed "$hmm" "$dir/terrain.png" "$dir/hmm.stl" -z "$zscale" -e "$he" -q)
            score=$("$bench" score --dir "$dir" --stl "$dir/hmm.stl" --match) ;;
          tinbase)
            rm -f "$dir/run.tinbase"*
            cp "$dir/base.tinbase" "$dir/run.tinbase"
            if [ -e "$dir/base.tinbase-wal" ]; then cp "$dir/base.tinbase-wal" "$dir/run.tinbase-wal"; fi
            read -r s k cpu < <(timed "$tinbase" --quiet tin build "$dir/run.tinbase" --surface s --tolerance "$e")
            score=$("$bench" score --dir "$dir" --store "$dir/run.tinbase" --surface s) ;;
          delatin)
            read -r s k cpu < <(timed node bench/peers/run_delatin.mjs "$dir/terrain.f32" "$n" "$n" "$e" "$dir/delatin.mesh")
            score=$("$bench" score --dir "$dir" --mesh "$dir/delatin.mesh" --match) ;;
        esac
        tri=$(sed 's/.*"triangles":\([0-9]*\).*/\1/' <<<"$score")
        err=$(sed 's/.*"max_error":\([0-9.e+-]*\).*/\1/' <<<"$score")
        same=$(grep -o '"tinbase_at_same_error":[0-9]*' <<<"$score" | cut -d: -f2 || true)
        echo "$n,$e,$rep,$tool,$s,$((k / 1024)),$tri,$err,$same,$cpu" | tee -a "$csv"
      done
    done
  done
done


echo
table "$csv"
