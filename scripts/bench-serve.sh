#!/usr/bin/env bash
# Issue 26's load benchmark of `tinbase serve`, with wrk (Debian) on loopback, on the ~1e6-triangle
# generated store of issue 24 (bench/store_1e6.h):
#   locate         GET /surfaces/terrain/locate?x=&y= at uniform random points, keep-alive
#                  (bench/serve_locate.lua): requests/s, p50, p99;
#   postgis        the same point query through PostGIS's own SQL on the same triangles (a GiST
#                  index, the triangle with its vertices, neighbours, lon/lat and the interpolated
#                  z), from pgbench with as many clients and prepared statements: transactions/s,
#                  p50, p99 (from its per-transaction log);
#   locate+writes  locate again while bench/serve_writer.py POSTs a small polygon every 100 ms;
#   locate-nocrs   locate on a copy of the store with its CRS taken out of meta, so the answers
#                  carry no lon/lat: what the lon/lat part of an answer costs;
#   floor-http     an answer with no store work (httplib's JSON 404 of an unknown path), and
#   floor-sql      SELECT 1 through pgbench: what the two sides cost before any query;
#   tiles-cold     every tile of the pyramid once, right after the server started, in random
#                  order (bench/serve_tiles_cold.lua; it gets 4 x DURATION to finish);
#   tiles-warm     tiles drawn at random from the same list, for DURATION (serve_tiles_warm.lua),
#                  gzip accepted as browsers do, and tiles-identity the same without gzip.
# Each round runs them all in turn (tinbase and PostGIS in alternating order), on a fresh copy of
# the store, so the ratios within a round compare runs that shared the machine alike. PostGIS is
# a throwaway PostgreSQL 15 + PostGIS 3 cluster (scripts/throwaway-postgis.sh).
#
# Usage: scripts/bench-serve.sh [OUTDIR] [ROUNDS]   (defaults build-bench/serve, 3)
# Environment: BUILD_DIR (build-bench), SOURCE_STORE (a locate_1e6.tinbase to copy; default:
#   locate_bench builds one in OUTDIR), DURATION (s per run, 15), CLIENTS (wrk threads, each with
#   one connection, and pgbench clients: 4), SERVER_THREADS (8), MAX_ZOOM (19; tiles build's
#   default, 17, gives 84 tiles, too few for a cold pass; 19 gives 798).
# Writes OUTDIR/runs.csv (every run of every round) and prints the summary; with RESULTS=FILE
# (bench/results/issue26_serve.csv) also appends every run to FILE as date,what,value,unit,notes,
# with NOTE (say what else the machine was doing) as the notes.
set -euo pipefail
cd "$(dirname "$0")/.."
. scripts/throwaway-postgis.sh
out=$(realpath -m "${1:-build-bench/serve}")
rounds=${2:-3}
build=${BUILD_DIR:-build-bench}
duration=${DURATION:-15}
clients=${CLIENTS:-4}
server_threads=${SERVER_THREADS:-8}
surface=terrain

if ! command -v wrk >/dev/null; then
  [ "$(id -u)" = 0 ] || { echo "wrk is missing: apt-get install wrk" >&2; exit 1; }
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq wrk >/dev/null
fi
pg_check_installed
mkdir -p "$out"
if [ ! -f "$build/build.ninja" ]; then
  cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DTINBASE_BUILD_BENCH=ON >/dev/null
fi
ninja -C "$build" tinbase locate_bench >/dev/null
tinbase=$(realpath "$build/apps/tinbase")

# The stores: base (the 1e6 triangles, copied afresh for every round's writes) and tiles (base
# with its tile pyramid, built once).
copy_store() {  # from, to
  rm -f "$2" "$2-wal" "$2-shm"
  cp "$1" "$2"
  if [ -s "$1-wal" ]; then cp "$1-wal" "$2-wal"; fi
}
if [ ! -f "$out/base.tinbase" ]; then
  source_store=${SOURCE_STORE:-}
  if [ -z "$source_store" ]; then
    "$build/bench/locate_bench" store --dir "$out"
    source_store=$out/locate_1e6.tinbase
  fi
  copy_store "$source_store" "$out/base.tinbase.part"
  mv "$out/base.tinbase.part" "$out/base.tinbase"
fi
if [ ! -f "$out/nocrs.tinbase" ]; then
  copy_store "$out/base.tinbase" "$out/nocrs.tinbase.part"
  sqlite3 "$out/nocrs.tinbase.part" "DELETE FROM meta WHERE key IN ('crs_wkt', 'crs_label')"
  mv "$out/nocrs.tinbase.part" "$out/nocrs.tinbase"
fi
if [ ! -f "$out/tiles.tinbase" ]; then
  copy_store "$out/base.tinbase" "$out/tiles.tinbase.part"
  "$tinbase" tiles build "$out/tiles.tinbase.part" --surface "$surface" \
    --max-zoom "${MAX_ZOOM:-19}" --extensions octvertexnormals,metadata >"$out/tiles_build.log"
  mv "$out/tiles.tinbase.part" "$out/tiles.tinbase"
fi
# The triangles for PostGIS, with their z, neighbours, visibility and tag as the store has them.
if [ ! -f "$out/triangles_z.tsv" ]; then
  sqlite3 -readonly -separator $'\t' "$out/base.tinbase" >"$out/triangles_z.tsv.part" <<SQL
SELECT t.id, printf('SRID=32632;POLYGON Z((%!.17g %!.17g %!.17g,%!.17g %!.17g %!.17g,%!.17g %!.17g %!.17g,%!.17g %!.17g %!.17g))',
         a.x, a.y, a.z, b.x, b.y, b.z, c.x, c.y, c.z, a.x, a.y, a.z),
       ifnull(t.n0, '\N'), ifnull(t.n1, '\N'), ifnull(t.n2, '\N'), t.visible, ifnull(t.tag, '\N')
  FROM triangles t JOIN surfaces s ON s.id = t.surface AND s.name = '$surface'
  JOIN vertices a ON a.id = t.v0 JOIN vertices b ON b.id = t.v1 JOIN vertices c ON c.id = t.v2;
SQL
  mv "$out/triangles_z.tsv.part" "$out/triangles_z.tsv"
fi

# tinbase serve on a store, in the background; sets server_pid and port.
server_pid=
start_server() {  # store
  "$tinbase" serve "$1" --listen 127.0.0.1:0 --threads "$server_threads" >"$out/serve.log" 2>&1 &
  server_pid=$!
  for _ in $(seq 1 200); do
    grep -q '^serving' "$out/serve.log" && break
    sleep 0.05
  done
  port=$(grep -o ':[0-9][0-9]*/' "$out/serve.log" | tr -d ':/')
  [ -n "$port" ] || { cat "$out/serve.log" >&2; exit 1; }
}
stop_server() {
  if [ -n "$server_pid" ]; then
    kill "$server_pid" 2>/dev/null || true
    wait "$server_pid" 2>/dev/null || true
    server_pid=
  fi
}
cleanup() { stop_server; pg_stop; }

pg_start
trap cleanup EXIT
t0=$(date +%s.%N)
"${psql[@]}" <<SQL
CREATE EXTENSION postgis;
CREATE TABLE tri (id bigint PRIMARY KEY, geom geometry(PolygonZ, 32632) NOT NULL,
                  n0 bigint, n1 bigint, n2 bigint, visible boolean NOT NULL, tag bigint);
\copy tri FROM '$out/triangles_z.tsv'
CREATE INDEX tri_geom ON tri USING gist (geom);
VACUUM ANALYZE;
SQL
echo "PostGIS: $("${psql[@]}" -c 'SELECT count(*) FROM tri') triangles loaded and indexed in" \
  "$(echo "$(date +%s.%N) - $t0" | bc) s"

# The box of the random points: the surface's extent less 1 cm (its boundary is its extent: the
# generated store covers its whole grid).
start_server "$out/tiles.tinbase"
read -r minx miny maxx maxy < <(python3 - "$port" "$surface" <<'PY'
import json, sys, urllib.request
surfaces = json.load(urllib.request.urlopen(f"http://127.0.0.1:{sys.argv[1]}/surfaces"))["surfaces"]
e = next(s for s in surfaces if s["name"] == sys.argv[2])["extent"]
print(e[0] + 0.01, e[1] + 0.01, e[3] - 0.01, e[4] - 0.01)
PY
)
# Every stored tile of the pyramid (the store's layer.json: the served one also lists the filler
# tiles of the levels above the coarsest stored one, every tile of levels 0-7 here), shuffled
# with a fixed seed.
"$tinbase" tiles info "$out/tiles.tinbase" --surface "$surface" --json >"$out/tiles_info.json"
python3 - "$out/tiles_info.json" "$surface" >"$out/tiles.txt" <<'PY'
import json, random, sys
surface = sys.argv[2]
layer = json.load(open(sys.argv[1]))["layer"]
paths = [f"/surfaces/{surface}/tiles/{z}/{x}/{y}.terrain"
         for z, rects in enumerate(layer["available"]) for r in rects
         for x in range(r["startX"], r["endX"] + 1) for y in range(r["startY"], r["endY"] + 1)]
random.Random(26).shuffle(paths)
print("\n".join(paths))
PY
stop_server
echo "box $minx $miny $maxx $maxy; $(wc -l <"$out/tiles.txt") tiles"

# PostGIS's answer to the point: the triangle (its vertices as GeoJSON, also in lon/lat), its
# neighbours, visibility, tag, and z interpolated in the plane of its vertices.
cat >"$out/pgbench_locate.sql" <<SQL
\set x $minx + random(0, 1000000000) * ($maxx - $minx) / 1000000000.0
\set y $miny + random(0, 1000000000) * ($maxy - $miny) / 1000000000.0
SELECT id, ST_AsGeoJSON(geom), ST_AsGeoJSON(ST_Transform(geom, 4326)), n0, n1, n2, visible, tag,
       (w0 * z0 + w1 * z1 + (d - w0 - w1) * z2) / d AS z
  FROM (SELECT id, geom, n0, n1, n2, visible, tag,
               ST_X(p0) AS x0, ST_Y(p0) AS y0, ST_Z(p0) AS z0, ST_Z(p1) AS z1, ST_Z(p2) AS z2,
               (ST_Y(p1) - ST_Y(p2)) * (:x - ST_X(p2)) + (ST_X(p2) - ST_X(p1)) * (:y - ST_Y(p2)) AS w0,
               (ST_Y(p2) - ST_Y(p0)) * (:x - ST_X(p2)) + (ST_X(p0) - ST_X(p2)) * (:y - ST_Y(p2)) AS w1,
               (ST_Y(p1) - ST_Y(p2)) * (ST_X(p0) - ST_X(p2)) + (ST_X(p2) - ST_X(p1)) * (ST_Y(p0) - ST_Y(p2)) AS d
          FROM (SELECT *, ST_PointN(ST_ExteriorRing(geom), 1) AS p0,
                       ST_PointN(ST_ExteriorRing(geom), 2) AS p1,
                       ST_PointN(ST_ExteriorRing(geom), 3) AS p2
                  FROM tri
                 WHERE ST_Intersects(geom, ST_SetSRID(ST_MakePoint(:x, :y), 32632))
                 LIMIT 1) t) u;
SQL

# CPU time of the serving processes, in clock ticks: tinbase serve's own; PostgreSQL's backends,
# which exit with their pgbench clients and are reaped by the postmaster, so they are counted in
# its children's time. On a shared machine this says more than requests/s.
tck=$(getconf CLK_TCK)
server_ticks() { awk '{print $14 + $15}' "/proc/$server_pid/stat"; }
pg_ticks() { awk '{print $16 + $17}' "/proc/$(head -1 "$pg_data/postmaster.pid")/stat"; }

runs=$out/runs.csv
echo "round,case,requests,seconds,requests_per_s,mib_per_s,p50_ms,p99_ms,max_ms,non_2xx,$(
  )socket_errors,server_cpu_us_per_request,notes" >"$runs"
record() {  # round, case, "wrk,requests,seconds,bytes,p50,p99,max,non_2xx,socket_errors", ticks, notes
  local n s bytes p50 p99 max bad sock
  IFS=, read -r _ n s bytes p50 p99 max bad sock <<<"$3"
  echo "$1,$2,$n,$s,$(echo "scale=1; $n / $s" | bc),$(echo "scale=2; $bytes / $s / 1048576" | bc),$(
    )$p50,$p99,$max,$bad,$sock,$(echo "scale=1; $4 * 1000000 / $tck / $n" | bc),$5" >>"$runs"
}
wrk_run() {  # script, wrk args after the URL...: the script's "wrk,..." line
  local script=$1
  shift
  wrk -t "$clients" -c "$clients" -d "${duration}s" --timeout 10s -s "bench/$script" \
    "http://127.0.0.1:$port" -- "$@" | grep '^wrk,'
}
wrk_case() {  # round, case, notes, script, script args...
  local round=$1 case=$2 notes=$3 cpu0 line
  shift 3
  cpu0=$(server_ticks)
  line=$(wrk_run "$@")
  record "$round" "$case" "$line" "$(($(server_ticks) - cpu0))" "$notes"
}
pgbench_case() {  # round, case, sql file, notes
  rm -f "$out"/pgbench_log*
  local cpu0 tps
  cpu0=$(pg_ticks)
  tps=$(cd "$out" && pg_bench_run -n -c "$clients" -j "$clients" -T "$duration" -M prepared \
    -l --log-prefix=pgbench_log -f "$3" 2>/dev/null | sed -n 's/^tps = \([0-9.]*\).*/\1/p')
  sleep 0.5  # the backends exit after their clients
  python3 - "$tps" "$duration" "$out"/pgbench_log* <<'PY' | { read -r line; record "$1" "$2" "$line" "$(($(pg_ticks) - cpu0))" "$4"; }
import sys
tps, seconds = float(sys.argv[1]), float(sys.argv[2])
lat = sorted(int(line.split()[2]) for f in sys.argv[3:] for line in open(f))  # µs
q = lambda p: lat[min(len(lat) - 1, int(p * len(lat)))] / 1e3
# As the wrk scripts' line; the seconds make the rate pgbench's tps.
print(f"wrk,{len(lat)},{len(lat) / tps:.3f},0,{q(0.5):.3f},{q(0.99):.3f},{lat[-1] / 1e3:.3f},0,0")
PY
}
locate() {  # round
  wrk_case "$1" locate "" serve_locate.lua "$surface" "$minx" "$miny" "$maxx" "$maxy"
}
postgis() {  # round
  pgbench_case "$1" postgis "$out/pgbench_locate.sql" "pgbench -M prepared"
}
locate_with_writes() {  # round
  local wfile=$out/writer.txt posts created other wp50 wmax werr
  python3 bench/serve_writer.py "$port" "$surface" "$minx" "$miny" "$maxx" "$maxy" \
    "$((duration + 1))" >"$wfile" &
  local writer=$!
  sleep 0.5
  wrk_case "$1" locate+writes "" serve_locate.lua "$surface" "$minx" "$miny" "$maxx" "$maxy"
  wait "$writer"
  IFS=, read -r _ posts created other wp50 wmax werr <"$wfile"
  sed -i "\$s/\$/writer: $posts posts; $created created; $other refused; p50 $wp50 ms; $(
    )max $wmax ms${werr:+; ${werr//\//\\/}}/" "$runs"
}
# The floors: an answer with no store work (httplib's 404 with a JSON body) and SELECT 1.
echo /bench-floor >"$out/floor.txt"
echo "SELECT 1;" >"$out/pgbench_floor.sql"
floors() {  # round
  wrk_case "$1" floor-http "404 of an unknown path" serve_tiles_warm.lua "$out/floor.txt"
  pgbench_case "$1" floor-sql "$out/pgbench_floor.sql" "SELECT 1"
}

for round in $(seq 1 "$rounds"); do
  copy_store "$out/base.tinbase" "$out/run.tinbase"
  start_server "$out/run.tinbase"
  if [ $((round % 2)) = 1 ]; then
    locate "$round"
    postgis "$round"
  else
    postgis "$round"
    locate "$round"
  fi
  locate_with_writes "$round"
  floors "$round"
  stop_server
  start_server "$out/nocrs.tinbase"
  wrk_case "$round" locate-nocrs "no lon/lat in the answers" \
    serve_locate.lua "$surface" "$minx" "$miny" "$maxx" "$maxy"
  stop_server
  start_server "$out/tiles.tinbase"
  cpu0=$(server_ticks)
  line=$(wrk -t "$clients" -c "$clients" -d "$((4 * duration))s" --timeout 10s \
    -s bench/serve_tiles_cold.lua "http://127.0.0.1:$port" -- "$out/tiles.txt" "$clients" |
    grep '^wrk,')
  record "$round" tiles-cold "$line" "$(($(server_ticks) - cpu0))" \
    "$(echo "$line" | cut -d, -f2) of $(wc -l <"$out/tiles.txt") tiles once each after the start"
  wrk_case "$round" tiles-warm "gzip" serve_tiles_warm.lua "$out/tiles.txt"
  wrk_case "$round" tiles-identity "no gzip" serve_tiles_warm.lua "$out/tiles.txt" identity
  stop_server
  tail -n +2 "$runs" | grep "^$round,"
done

python3 - "$runs" <<'PY'
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
by = {}
for r in rows:
    by.setdefault(r["case"], {})[r["round"]] = r
print("\ncase,rounds,median requests/s,median p50 ms,median p99 ms,median server CPU us/request,"
      "non-2xx,socket errors")
for case, v in by.items():
    med = lambda k: statistics.median(float(r[k]) for r in v.values())
    print(f"{case},{len(v)},{med('requests_per_s'):.0f},{med('p50_ms'):.3f},{med('p99_ms'):.3f},"
          f"{med('server_cpu_us_per_request'):.1f},{sum(int(r['non_2xx']) for r in v.values())},"
          f"{sum(int(r['socket_errors']) for r in v.values())}")
def ratios(a, b, key):
    return [float(by[a][k][key]) / float(by[b][k][key]) for k in by.get(a, {}) if k in by.get(b, {})]
print("\nratio per round [goal]")
for a, b, key, goal in [("locate", "postgis", "requests_per_s", ">= 5"),
                        ("postgis", "locate", "server_cpu_us_per_request", ""),
                        ("locate-nocrs", "postgis", "requests_per_s", ""),
                        ("postgis", "locate-nocrs", "server_cpu_us_per_request", ""),
                        ("locate+writes", "locate", "p99_ms", "< 3"),
                        ("floor-http", "floor-sql", "requests_per_s", ""),
                        ("tiles-warm", "tiles-cold", "requests_per_s", ""),
                        ("tiles-identity", "tiles-warm", "requests_per_s", "")]:
    v = ratios(a, b, key)
    if v:
        print(f"{a} / {b} {key}: " + ", ".join(f"{x:.2f}" for x in v) + f" [{goal}]")
PY

[ -z "${RESULTS:-}" ] || python3 - "$runs" "$RESULTS" "${NOTE:-}" <<'PY'
import csv, datetime, sys
rows = list(csv.DictReader(open(sys.argv[1])))
today, note = datetime.date.today().isoformat(), sys.argv[3]
with open(sys.argv[2], "a", newline="") as f:
    w = csv.writer(f)
    for r in rows:
        what = f"serve {r['case']}, round {r['round']}"
        for key, unit in [("requests_per_s", "1/s"), ("p50_ms", "ms"), ("p99_ms", "ms"),
                          ("server_cpu_us_per_request", "us"), ("non_2xx", "")]:
            w.writerow([today, f"{what}, {key}", r[key], unit, note])
        if r["notes"]:
            w.writerow([today, f"{what}, notes", "", "", r["notes"]])
PY
