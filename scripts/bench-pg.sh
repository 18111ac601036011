#!/usr/bin/env bash
# Issue 27's speed table: the same workloads on SQLite and PostgreSQL in one run
# (bench/pg_speed_bench.cc: bulk TIN write of ~1e6 triangles, point location, single-polygon
# insert latency). The PostgreSQL 15 + PostGIS server is a throwaway one (scripts/pg-server.sh),
# started with its durability settings back on (fsync, synchronous_commit, full_page_writes), as
# SQLite's stores commit durably too; it is stopped and removed at the end.
#
# Usage: scripts/bench-pg.sh [OUTDIR] [ROUNDS]   (defaults build-bench/pg, 3)
#   In the environment: BUILD_DIR (build-bench), INSERTS (10), STORED_POINTS (20000),
#   BULK_POINTS (1000000).
# Writes OUTDIR/run.txt (every round, then the summary table).
set -euo pipefail
cd "$(dirname "$0")/.."
out=$(realpath -m "${1:-build-bench/pg}")
rounds=${2:-3}
build=${BUILD_DIR:-build-bench}
mkdir -p "$out"
if [ ! -f "$build/build.ninja" ]; then
  cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DTINBASE_BUILD_BENCH=ON >/dev/null
fi
ninja -C "$build" pg_speed_bench >/dev/null
server="$out/server"
scripts/pg-server.sh stop "$server"
url=$(scripts/pg-server.sh start "$server" -c fsync=on -c synchronous_commit=on \
  -c full_page_writes=on -c max_parallel_workers_per_gather=0)
trap 'scripts/pg-server.sh stop "$server"' EXIT
"$build/bench/pg_speed_bench" --dir "$out" --postgres "$url" --rounds "$rounds" \
  --inserts "${INSERTS:-10}" --stored-points "${STORED_POINTS:-20000}" \
  --bulk-points "${BULK_POINTS:-1000000}" | tee "$out/run.txt"
