#!/usr/bin/env bash
# Issue 24's bulk point location benchmark: tinbase's LocatePoints (in memory for a large request,
# and forced onto the stored walk) and PointLocator against CGAL's in-memory locate()
# (bench/locate_bench.cc) and PostGIS ST_Intersects on a GiST-indexed triangle table, on
# the ~1e6-triangle generated store. Each round runs every tinbase and CGAL case, then PostGIS on
# the first SAMPLE random points (and the same points in Hilbert order): one SQL join (one client,
# no parallel workers) and one query per point through pgbench (one client, prepared statements).
# PostgreSQL 15 + PostGIS 3 (Debian postgresql-15, postgresql-15-postgis-3) run from a temporary
# cluster on a free loopback port, stopped and removed at the end. The server runs without JIT
# (its compile time is per statement, not per point) and without parallel workers (one
# client, one core).
#
# Usage: scripts/bench-locate.sh [OUTDIR] [POINTS] [ROUNDS]
#   (defaults build-bench/locate, 10000000, 2). In the environment: SAMPLE (PostGIS's points,
#   100000), WALK_SAMPLE (random points for the walks from the last answer, 2000), JUMP_POINTS
#   (random points for tinbase-jump and tinbase-stored, 1000000), METHODS (locate_bench's,
#   default all but tinbase and tinbase+cache, which tinbase-stored stands for), BUILD_DIR
#   (build-bench).
# Writes OUTDIR/runs.csv (every case of every round) and prints the summary.
set -euo pipefail
cd "$(dirname "$0")/.."
out=$(realpath -m "${1:-build-bench/locate}")
points=${2:-10000000}
rounds=${3:-2}
sample=${SAMPLE:-100000}
walk_sample=${WALK_SAMPLE:-2000}
jump_points=${JUMP_POINTS:-1000000}
methods=${METHODS:-tinbase-bulk,tinbase-memory-walk,tinbase-stored,tinbase-jump,cgal-walk,cgal-hierarchy}
build=${BUILD_DIR:-build-bench}
pgbin=/usr/lib/postgresql/15/bin
[ -x "$pgbin/initdb" ] || { echo "PostgreSQL 15 is missing: apt-get install postgresql-15 postgresql-15-postgis-3" >&2; exit 1; }
[ -f /usr/share/postgresql/15/extension/postgis.control ] || { echo "PostGIS for PostgreSQL 15 is missing: apt-get install postgresql-15-postgis-3" >&2; exit 1; }

mkdir -p "$out"
if [ ! -f "$build/build.ninja" ]; then
  cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DTINBASE_BUILD_BENCH=ON >/dev/null
fi
ninja -C "$build" locate_bench >/dev/null
bench=$build/bench/locate_bench
"$bench" store --dir "$out"
"$bench" postgis-files --dir "$out" --sample "$sample"

# A throwaway cluster. initdb refuses to run as root, so the server runs as the postgres user.
pgdata=$(mktemp -d /tmp/tinbase-pg.XXXXXX)
as_pg=()
if [ "$(id -u)" = 0 ]; then chown postgres "$pgdata"; as_pg=(runuser -u postgres --); fi
port=$(python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
stop_server() {
  "${as_pg[@]}" "$pgbin/pg_ctl" -D "$pgdata" -m fast stop >/dev/null 2>&1 || true
  rm -rf "$pgdata"
}
trap stop_server EXIT
"${as_pg[@]}" "$pgbin/initdb" -D "$pgdata" -U bench --auth=trust >/dev/null
"${as_pg[@]}" "$pgbin/pg_ctl" -D "$pgdata" -l "$pgdata/server.log" -w \
  -o "-p $port -c listen_addresses=127.0.0.1 -k $pgdata -c shared_buffers=1GB -c fsync=off \
      -c max_parallel_workers_per_gather=0 -c jit=off" start >/dev/null
psql=("$pgbin/psql" -h 127.0.0.1 -p "$port" -U bench -d postgres -v ON_ERROR_STOP=1 -qAt)

now() { date +%s.%N; }
t0=$(now)
"${psql[@]}" <<SQL
CREATE EXTENSION postgis;
CREATE TABLE tri (id bigint PRIMARY KEY, geom geometry(Polygon, 32632) NOT NULL);
\copy tri FROM '$out/triangles.tsv'
CREATE INDEX tri_geom ON tri USING gist (geom);
CREATE TABLE pts_random (i int PRIMARY KEY, x float8, y float8);
CREATE TABLE pts_sorted (i int PRIMARY KEY, x float8, y float8);
\copy pts_random FROM '$out/points_random.tsv'
\copy pts_sorted FROM '$out/points_sorted.tsv'
VACUUM ANALYZE;
SQL
echo "PostGIS: triangles loaded and indexed in $(echo "$(now) - $t0" | bc) s"
# One statement per point, the point drawn at random from the sample by pgbench.
cat >"$out/pgbench_locate.sql" <<'SQL'
\set i random(0, :n - 1)
SELECT t.id FROM pts_random p JOIN tri t ON ST_Intersects(t.geom, ST_SetSRID(ST_MakePoint(p.x, p.y), 32632)) WHERE p.i = :i;
SQL

# As locate_bench's rows: ns_per_point is CPU time (of the server backend for PostGIS's join: on
# a machine shared with other work, wall time measures the scheduler as much as the method).
runs=$out/runs.csv
echo "round,method,order,points,seconds,cpu_seconds,ns_per_point,wall_ns_per_point,mean_steps,checksum" >"$runs"
tck=$(getconf CLK_TCK)
postgis_join() {  # round, order
  local r
  r=$("${psql[@]}" <<SQL
SELECT pg_backend_pid() AS pid \gset
\setenv BACKEND :pid
\! awk '{print "cpu0," \$14 + \$15}' /proc/\$BACKEND/stat
\timing on
SELECT 'result,' || count(*) || ',' || sum(t.id) FROM pts_$2 p JOIN tri t
  ON ST_Intersects(t.geom, ST_SetSRID(ST_MakePoint(p.x, p.y), 32632));
\timing off
\! awk '{print "cpu1," \$14 + \$15}' /proc/\$BACKEND/stat
SQL
)
  python3 - "$1" "$2" "$tck" "$r" >>"$runs" <<'PY'
import re, sys
round_, order, tck, text = sys.argv[1], sys.argv[2], float(sys.argv[3]), sys.argv[4]
v = dict(line.split(",", 1) for line in text.splitlines() if "," in line)
count, checksum = v["result"].split(",")
wall = float(re.search(r"Time: ([0-9.]+) ms", text).group(1)) / 1000
cpu = (float(v["cpu1"]) - float(v["cpu0"])) / tck
n = int(count)
print(f"{round_},postgis-join,{order},{n},{wall:.3f},{cpu:.3f},{cpu * 1e9 / n:.1f},"
      f"{wall * 1e9 / n:.1f},,{checksum}")
PY
}
postgis_pgbench() {  # round
  local tps
  tps=$(PGPASSWORD= "$pgbin/pgbench" -h 127.0.0.1 -p "$port" -U bench -n -c 1 -T 15 -M prepared \
        -D n="$sample" -f "$out/pgbench_locate.sql" postgres 2>/dev/null |
        sed -n 's/^tps = \([0-9.]*\).*/\1/p')
  # Round trips on one client: wall time is what it measures (its CPU column stays empty).
  echo "$1,postgis-pgbench,random,$(printf '%.0f' "$(echo "$tps * 15" | bc)"),15,,$(echo "1000000000 / $tps" | bc),$(echo "1000000000 / $tps" | bc),," >>"$runs"
}
for round in $(seq 1 "$rounds"); do
  "$bench" run --dir "$out" --points "$points" --sample "$sample" --walk-sample "$walk_sample" \
    --jump-points "$jump_points" --methods "$methods" --rounds 1 |
    grep '^1,' | sed "s/^1,/$round,/" >>"$runs"
  postgis_join "$round" random
  postgis_join "$round" sorted
  postgis_pgbench "$round"
  tail -n +2 "$runs" | grep "^$round,"
done

python3 - "$runs" <<'PY'
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
ns, wall = {}, {}
for r in rows:
    key = (r["method"], r["order"])
    ns.setdefault(key, {})[r["round"]] = float(r["ns_per_point"])
    wall.setdefault(key, {})[r["round"]] = float(r["wall_ns_per_point"])
def ratios(a, b, table):  # a / b within each round
    return [table[a][k] / table[b][k] for k in table.get(a, {}) if k in table.get(b, {})]
print("\nmethod,order,points,median CPU ns/point,median wall ns/point,points/s (CPU)")
for key, v in sorted(ns.items()):
    pts = next(r["points"] for r in rows if (r["method"], r["order"]) == key)
    med = statistics.median(v.values())
    print(f"{key[0]},{key[1]},{pts},{med:.0f},{statistics.median(wall[key].values()):.0f},"
          f"{1e9 / med:.0f}")
print("\nratio per round, CPU time unless it says wall [goal]")
for a, b, table, goal in [
        (("tinbase-bulk", "sorted"), ("cgal-walk", "sorted"), ns, "<= 2"),
        (("tinbase-memory-walk", "sorted"), ("cgal-walk", "sorted"), ns, "<= 2, walk alone"),
        (("tinbase-bulk", "random"), ("cgal-hierarchy", "random"), ns, "<= 2"),
        (("tinbase-memory-walk", "random"), ("cgal-hierarchy", "random"), ns, "walk alone"),
        (("postgis-join", "sorted"), ("tinbase-bulk", "sorted"), ns, ">= 20"),
        (("postgis-join", "random"), ("tinbase-bulk", "random"), ns, ">= 20"),
        (("tinbase-stored", "sorted"), ("tinbase-bulk", "sorted"), ns, "speed-up"),
        (("tinbase-stored", "random"), ("tinbase-bulk", "random"), ns, "speed-up"),
        (("tinbase", "sorted"), ("cgal-walk", "sorted"), ns, "<= 2"),
        (("tinbase+cache", "sorted"), ("cgal-walk", "sorted"), ns, "<= 2"),
        (("tinbase-jump", "random"), ("cgal-hierarchy", "random"), ns, "<= 2"),
        (("tinbase", "random"), ("cgal-walk", "random"), ns, ""),
        (("postgis-join", "random"), ("tinbase-jump", "random"), ns, ">= 20"),
        (("postgis-pgbench", "random"), ("tinbase-jump", "random"), wall, ">= 20, wall")]:
    v = ratios(a, b, table)
    if v:
        print(f"{a[0]} {a[1]} / {b[0]} {b[1]}: " + ", ".join(f"{x:.2f}" for x in v) + f" [{goal}]")
PY
