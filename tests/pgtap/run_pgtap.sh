#!/usr/bin/env bash
# The pgTAP tests of the PostgreSQL extension (CTest runs this; tests/CMakeLists.txt):
#   tests/pgtap/run_pgtap.sh TINBASE_CLI EXTENSION_DIR
# starts a throwaway server with the extension's files (scripts/pg-server.sh --extension-dir),
# makes a store with CREATE EXTENSION tinbase, builds a surface into it with the CLI, records the
# CLI's answers for a set of points (table public.cli_answers), then runs every tests/pgtap/*.sql
# with pg_prove. A missing pgTAP or pg_prove fails the test, saying which package to install.
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
trap '[ -n "${TINBASE_PGTAP_KEEP:-}" ] || "$root/scripts/pg-server.sh" stop "$dir/server"' EXIT
url=$("$root/scripts/pg-server.sh" start "$dir/server" --extension-dir "$ext")
port=${url##*:}
port=${port%%/*}
psql=(psql "$url" -qAt -v ON_ERROR_STOP=1)

"${psql[@]}" -c "CREATE EXTENSION pgtap; CREATE SCHEMA terrain; CREATE EXTENSION tinbase SCHEMA terrain"
store="$url?schema=terrain"
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

pg_prove -h 127.0.0.1 -p "$port" -U tinbase -d tinbase "$here"/*.sql
