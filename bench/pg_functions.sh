#!/usr/bin/env bash
# Issue 27's SQL function benchmark: tinbase_z from SQL over a table of wells, against PostGIS
# ST_Intersects on a GiST-indexed triangle table of the same surface plus the z interpolated in
# SQL in the triangle's plane, in one throwaway PostgreSQL 15 + PostGIS 3 server
# (scripts/pg-server.sh with the build's extension). The store is the Hamersley DEM built by the
# CLI into a schema made by CREATE EXTENSION tinbase; the wells are WELLS random points over the
# surface's box (the same table for both; PostGIS gets them as ready-made point geometries).
# Each round runs tinbase, then PostGIS, ROUNDS times; the first tinbase statement of the run
# reads the surface into the backend (its time is reported on its own, as `tinbase-first`).
# Time is the server backend's CPU time (/proc/PID/stat; the machine is shared) and wall time.
#
# Usage: bench/pg_functions.sh TINBASE_CLI EXTENSION_DIR [OUTDIR] [WELLS] [ROUNDS]
#   (EXTENSION_DIR: the build's extensions/postgresql/extension; defaults build-bench/pg_functions,
#   1000000, 3). Writes OUTDIR/runs.csv and prints it with the ratios.
set -euo pipefail
cli=$(realpath "${1:?usage: bench/pg_functions.sh TINBASE_CLI EXTENSION_DIR [OUTDIR] [WELLS] [ROUNDS]}")
ext=$(realpath "${2:?usage: bench/pg_functions.sh TINBASE_CLI EXTENSION_DIR [OUTDIR] [WELLS] [ROUNDS]}")
cd "$(dirname "$0")/.."
out=$(realpath -m "${3:-build-bench/pg_functions}")
wells=${4:-1000000}
rounds=${5:-3}
mkdir -p "$out"
server=$(mktemp -d /tmp/tinbase-pgfn.XXXXXX)
chmod 755 "$server"
trap 'scripts/pg-server.sh stop "$server/pg"; rm -rf "$server"' EXIT
url=$(scripts/pg-server.sh start "$server/pg" --extension-dir "$ext" -c max_parallel_workers_per_gather=0)
psql=(psql "$url" -qAt -v ON_ERROR_STOP=1)
"${psql[@]}" -c "CREATE SCHEMA terrain; CREATE EXTENSION tinbase SCHEMA terrain"
store="$url?schema=terrain"
"$cli" dem import "$store" tests/data/geology/hamersley/dtm_rp.tif >/dev/null
"$cli" tin build "$store" --surface terrain --tolerance 2 >/dev/null

"${psql[@]}" <<SQL
SELECT setseed(0.27);
CREATE TABLE wells AS
SELECT i, x, y, ST_MakePoint(x, y) AS geom FROM (
  SELECT i, b.min_x + random() * (b.max_x - b.min_x) AS x, b.min_y + random() * (b.max_y - b.min_y) AS y
  FROM generate_series(1, $wells) i,
       (SELECT min(x) AS min_x, max(x) AS max_x, min(y) AS min_y, max(y) AS max_y
        FROM terrain.vertices) b) p;
-- The peer: each triangle as a polygon with its corners' coordinates, on a GiST index.
CREATE TABLE tri AS
SELECT t.id, ST_MakePolygon(ST_MakeLine(ARRAY[ST_MakePoint(a.x, a.y), ST_MakePoint(b.x, b.y),
                                               ST_MakePoint(c.x, c.y), ST_MakePoint(a.x, a.y)])) AS geom,
       a.x AS ax, a.y AS ay, a.z AS az, b.x AS bx, b.y AS by_, b.z AS bz, c.x AS cx, c.y AS cy,
       c.z AS cz
FROM terrain.triangles t JOIN terrain.vertices a ON a.id = t.v0
  JOIN terrain.vertices b ON b.id = t.v1 JOIN terrain.vertices c ON c.id = t.v2;
CREATE INDEX tri_geom ON tri USING gist(geom);
VACUUM ANALYZE wells;
VACUUM ANALYZE tri;
SQL
triangles=$("${psql[@]}" -c "SELECT count(*) FROM tri")

tinbase_sql="SELECT 'result,' || count(z) || ',' || round(sum(z)::numeric, 3) FROM (
  SELECT terrain.tinbase_z('terrain', x, y) AS z FROM wells) s;"
postgis_sql="SELECT 'result,' || count(z) || ',' || round(sum(z)::numeric, 3) FROM wells w
  CROSS JOIN LATERAL (
    SELECT ((bx - w.x) * (cy - w.y) - (by_ - w.y) * (cx - w.x)) * az / d +
           ((cx - w.x) * (ay - w.y) - (cy - w.y) * (ax - w.x)) * bz / d +
           ((ax - w.x) * (by_ - w.y) - (ay - w.y) * (bx - w.x)) * cz / d AS z
    FROM (SELECT *, (bx - ax) * (cy - ay) - (by_ - ay) * (cx - ax) AS d FROM tri t
          WHERE ST_Intersects(t.geom, w.geom) LIMIT 1) k) i;"

runs=$out/runs.csv
echo "round,method,wells,triangles,cpu_seconds,wall_seconds,ns_per_well,located,z_sum" >"$runs"
tck=$(getconf CLK_TCK)
# One session per round: tinbase's first statement (which reads the surface into the backend),
# tinbase again (the surface kept), then PostGIS; the backend's CPU time read between them.
for r in $(seq 1 "$rounds"); do
  text=$("${psql[@]}" <<SQL
SELECT pg_backend_pid() AS pid \gset
\setenv BACKEND :pid
\timing on
\! awk '{print "cpu," \$14 + \$15}' /proc/\$BACKEND/stat
$tinbase_sql
\! awk '{print "cpu," \$14 + \$15}' /proc/\$BACKEND/stat
$tinbase_sql
\! awk '{print "cpu," \$14 + \$15}' /proc/\$BACKEND/stat
$postgis_sql
\! awk '{print "cpu," \$14 + \$15}' /proc/\$BACKEND/stat
SQL
)
  python3 - "$r" "$wells" "$triangles" "$tck" "$text" >>"$runs" <<'PY'
import re, sys
round_, wells, triangles, tck, text = sys.argv[1:6]
cpu = [float(l.split(",")[1]) for l in text.splitlines() if l.startswith("cpu,")]
results = [l.split(",")[1:] for l in text.splitlines() if l.startswith("result,")]
walls = [float(t) / 1000 for t in re.findall(r"Time: ([0-9.]+) ms", text)]
walls = [w for w in walls][-3:]  # the three measured statements
for k, method in enumerate(["tinbase-first-statement", "tinbase", "postgis"]):
    c = (cpu[k + 1] - cpu[k]) / float(tck)
    print(f"{round_},{method},{wells},{triangles},{c:.3f},{walls[k]:.3f},"
          f"{c * 1e9 / int(wells):.1f},{results[k][0]},{results[k][1]}")
PY
done
cat "$runs"
python3 - "$runs" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
for r in sorted({row["round"] for row in rows}):
    by = {row["method"]: row for row in rows if row["round"] == r}
    pg = float(by["postgis"]["cpu_seconds"])
    print(f"round {r}: PostGIS / tinbase CPU: kept surface {pg / float(by['tinbase']['cpu_seconds']):.1f}, "
          f"first statement {pg / float(by['tinbase-first-statement']['cpu_seconds']):.1f}; "
          f"located {by['postgis']['located']} / {by['tinbase']['located']}; "
          f"z sums {by['postgis']['z_sum']} / {by['tinbase']['z_sum']}")
PY
