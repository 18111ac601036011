#!/usr/bin/env bash
# The pgTAP tests of the PostgreSQL extension (CTest runs this; tests/CMakeLists.txt):
#   tests/pgtap/run_pgtap.sh TINBASE_CLI EXTENSION_DIR
# starts a throwaway server with the extension's files (scripts/pg-server.sh --extension-dir),
# makes a store with CREATE EXTENSION tinbase (and one with `tinbase init`, to compare), builds a
# surface into the first with the CLI, records the CLI's answers for a set of points (table
# public.cli_answers), its profiles of random lines and its check of a damaged surface, dumps and
# restores the store (pg_dump), then runs every tests/pgtap/*.sql with pg_prove. Then it commits
# an edit by tinbase_add_polygon, makes the same edit with the CLI on a twin of the store, checks
# both with `tinbase check --full` and runs tests/pgtap/committed_edit/*.sql. A missing pgTAP
# or pg_prove fails the test, saying which package to install.
# TINBASE_PGTAP_KEEP=1 keeps the server and its directory (under /tmp) for a look afterwards.
set -euo pipefail
cli=${1:?usage: run_pgtap.sh TINBASE_CLI EXTENSION_DIR}
ext=${2:?usage: run_pgtap.sh TINBASE_CLI EXTENSION_DIR}
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)

command -v pg_prove >/dev/null ||
  { echo "run_pgtap: pg_prove is missing (apt-get install libtap-parser-sourcehandler-pgtap-perl)" >&2; exit 1; }
[ -f /usr/share/postgresql/15/extension/pgtap.control ] ||
  { echo "run_pgtap: pgTAP is missing (apt-get install postgresql-15-pgtap)" >&2; exit 1; }

dir=$(mktemp -d /tmp/tinbase-pgtap.XXXXXX)
chmod 755 "$dir"  # the server may run as the postgres user (scripts/pg-server.sh)
trap '[ -n "${TINBASE_PGTAP_KEEP:-}" ] || { "$root/scripts/pg-server.sh" stop "$dir/server"; rm -rf "$dir"; }' EXIT
url=$("$root/scripts/pg-server.sh" start "$dir/server" --extension-dir "$ext")
port=${url##*:}
port=${port%%/*}
psql=(psql "$url" -qAt -v ON_ERROR_STOP=1)

"${psql[@]}" -c "CREATE EXTENSION pgtap; CREATE SCHEMA terrain; CREATE EXTENSION tinbase SCHEMA terrain"
store="$url?schema=terrain"
# A store made the CLI's way beside it, for same_store_test.sql.
"$cli" init "$url?schema=cli_made" >/dev/null
"$cli" dem import "$store" "$root/tests/data/geology/hamersley/dtm_rp.tif" >/dev/null
"$cli" tin build "$store" --surface terrain --tolerance 10 >/dev/null
"$cli" check --full "$store" >/dev/null

# 300 points over the DEM's box and a margin around it (some fall outside the surface), with the
# CLI's triangle and z for each.
awk 'BEGIN { srand(27); for (i = 0; i < 300; ++i)
  printf "%.6f,%.6f\n", 503000 + rand() * 72000, 7460000 + rand() * 75000 }' >"$dir/points.csv"
"$cli" locate "$store" --surface terrain --points "$dir/points.csv" >"$dir/answers.csv"
"${psql[@]}" -c "CREATE TABLE public.cli_answers(x double precision, y double precision,
  triangle bigint, z double precision, visible boolean, tag text)"
"${psql[@]}" -c "\\copy public.cli_answers FROM '$dir/answers.csv' WITH (FORMAT csv, HEADER true)"

# 20 lines of three points inside the surface, with the CLI's profile of each (public.cli_profile,
# the stations in order as `seq`; public.profile_lines, the lines as WKT).
awk 'BEGIN { srand(28); for (i = 1; i <= 20; ++i) {
  printf "%d", i; for (k = 0; k < 3; ++k) printf " %.3f,%.3f", 512000 + rand() * 54000, 7468000 + rand() * 58000
  printf "\n" } }' >"$dir/lines.txt"
: >"$dir/profiles.csv"
: >"$dir/lines.csv"
while read -r id p1 p2 p3; do
  "$cli" profile "$store" --surface terrain --line "$p1 $p2 $p3" |
    awk -v id="$id" 'NR > 1 { printf "%d,%d,%s\n", id, NR - 1, $0 }' >>"$dir/profiles.csv"
  echo "$id,LINESTRING(${p1/,/ }, ${p2/,/ }, ${p3/,/ })" | sed 's/,LINESTRING/,"LINESTRING/; s/$/"/' >>"$dir/lines.csv"
done <"$dir/lines.txt"
"${psql[@]}" -c "CREATE TABLE public.cli_profile(line integer, seq integer, distance double precision,
  x double precision, y double precision, z double precision, kind text, triangle bigint,
  visible boolean, tag text)"
"${psql[@]}" -c "\\copy public.cli_profile FROM '$dir/profiles.csv' WITH (FORMAT csv)"
"${psql[@]}" -c "CREATE TABLE public.profile_lines(line integer, wkt text)"
"${psql[@]}" -c "\\copy public.profile_lines FROM '$dir/lines.csv' WITH (FORMAT csv)"

# The same damage seen by `tinbase check` and by tinbase_check(): a link to no triangle, a
# clockwise triangle, a tag that is not a row (committed, so the CLI sees it), then repaired.
# public.cli_problems holds every problem the CLI reports,
# public.sql_problems the function's.
"${psql[@]}" <<'SQL'
CREATE TABLE public.saved AS SELECT * FROM terrain.triangles WHERE id IN (100, 200, 300);
UPDATE terrain.triangles SET n0 = 99999999 WHERE id = 100;
UPDATE terrain.triangles SET v0 = v1, v1 = v0 WHERE id = 200;
UPDATE terrain.triangles SET tag = 77 WHERE id = 300;
CREATE TABLE public.sql_problems AS SELECT * FROM terrain.tinbase_check('terrain');
CREATE TABLE public.cli_problems(problem text, triangle_id bigint, detail text);
SQL
if "$cli" check --json "$store" >"$dir/check.json"; then
  echo "run_pgtap: tinbase check passed a damaged store" >&2
  exit 1
fi
python3 - "$dir/check.json" >"$dir/problems.csv" <<'PY'
import csv, json, sys
out = csv.writer(sys.stdout)
for p in json.load(open(sys.argv[1]))["problems"]:
    out.writerow([p["code"], p.get("triangle"), p["message"].split(": ", 1)[-1]])
PY
"${psql[@]}" -c "\\copy public.cli_problems FROM '$dir/problems.csv' WITH (FORMAT csv)"
"${psql[@]}" -c "UPDATE terrain.triangles t SET v0 = s.v0, v1 = s.v1, n0 = s.n0, tag = s.tag
  FROM public.saved s WHERE t.id = s.id"
"$cli" check --full "$store" >/dev/null

# pg_dump keeps an extension-made store: restored into a new database, it checks clean and holds
# the same rows.
pg_dump -h 127.0.0.1 -p "$port" -U tinbase -d tinbase -Fc -f "$dir/store.dump"
psql "${url%/*}/postgres" -qAt -v ON_ERROR_STOP=1 -c "CREATE DATABASE restored"
pg_restore -h 127.0.0.1 -p "$port" -U tinbase -d restored --exit-on-error "$dir/store.dump"
"$cli" check --full "${url%/*}/restored?schema=terrain" >/dev/null
count_rows="SELECT (SELECT count(*) FROM terrain.triangles) || ' ' ||
  (SELECT count(*) FROM terrain.vertices) || ' ' || (SELECT count(*) FROM terrain.meta) || ' ' ||
  (SELECT count(*) FROM terrain.tinbase_store)"
[ "$(psql "${url%/*}/restored" -qAt -c "$count_rows")" = "$("${psql[@]}" -c "$count_rows")" ] ||
  { echo "run_pgtap: the restored store differs from the dumped one" >&2; exit 1; }

pg_prove -h 127.0.0.1 -p "$port" -U tinbase -d tinbase "$here"/*.sql

# The committed edit: a square added to `terrain` by tinbase_add_polygon in a committed
# transaction, and by `tinbase polygon add` to `twin`, the same surface built by the CLI. Both
# must check clean (the CLI's check --full fails the script otherwise); committed_edit/ compares
# their rows.
twin="$url?schema=twin"
"$cli" init "$twin" >/dev/null
"$cli" dem import "$twin" "$root/tests/data/geology/hamersley/dtm_rp.tif" >/dev/null
"$cli" tin build "$twin" --surface terrain --tolerance 10 >/dev/null
# A sequence never takes back a number, and edit_test.sql's edits rolled back after drawing ids:
# `terrain` starts the edit from the twin's sequence positions, so that the rows compare by id.
for seq in dems_id_seq surfaces_id_seq vertices_id_seq tags_id_seq triangles_id_seq \
  features_id_seq changes_tx_seq; do
  "${psql[@]}" -c "SELECT setval('terrain.$seq', last_value, is_called) FROM twin.$seq" >/dev/null
done
square='[[530000, 7490000], [534000, 7490000], [534000, 7494000], [530000, 7494000], [530000, 7490000]]'
"${psql[@]}" -c "BEGIN; SELECT terrain.tinbase_add_polygon('terrain',
  'POLYGON((530000 7490000, 534000 7490000, 534000 7494000, 530000 7494000, 530000 7490000))',
  'fill', 'lake'); COMMIT;" >/dev/null
echo "{\"type\": \"FeatureCollection\",
  \"crs\": {\"type\": \"name\", \"properties\": {\"name\": \"EPSG:28350\"}}, \"features\": [{\"type\": \"Feature\", \"properties\": {},
  \"geometry\": {\"type\": \"Polygon\", \"coordinates\": [$square]}}]}" >"$dir/square.geojson"
"$cli" polygon add "$twin" "$dir/square.geojson" --surface terrain --mode fill --tag lake >/dev/null
"$cli" check --full "$store" >/dev/null
"$cli" check --full "$twin" >/dev/null
pg_prove -h 127.0.0.1 -p "$port" -U tinbase -d tinbase "$here"/committed_edit/*.sql
