#!/usr/bin/env bash
# A throwaway PostgreSQL 15 with PostGIS for the tests (and anyone trying the PostgreSQL backend):
# a cluster initialised in DIR, on a free port of 127.0.0.1 only, with trust authentication for
# the local user `tinbase`, a database `tinbase` with PostGIS, nothing kept after `stop`.
#   scripts/pg-server.sh start DIR   starts it; prints its URL, also written to DIR/url
#   scripts/pg-server.sh stop DIR    stops it and removes DIR
# Needs Debian's postgresql-15 and postgresql-15-postgis-3 (scripts/install-deps.sh). initdb
# refuses to run as root, so as root the server runs as the postgres user.
set -euo pipefail
action=${1:-}
dir=${2:-}
[ -n "$action" ] && [ -n "$dir" ] || { echo "usage: scripts/pg-server.sh start|stop DIR" >&2; exit 2; }
pgbin=/usr/lib/postgresql/15/bin
as_pg=()
[ "$(id -u)" = 0 ] && as_pg=(runuser -u postgres --)

case "$action" in
  start)
    [ -x "$pgbin/initdb" ] || { echo "pg-server: PostgreSQL 15 is missing (apt-get install postgresql-15)" >&2; exit 1; }
    [ -f /usr/share/postgresql/15/extension/postgis.control ] ||
      { echo "pg-server: PostGIS is missing (apt-get install postgresql-15-postgis-3)" >&2; exit 1; }
    mkdir -p "$dir"
    dir=$(cd "$dir" && pwd)
    [ "$(id -u)" = 0 ] && chown postgres "$dir"
    "${as_pg[@]}" "$pgbin/initdb" -D "$dir/data" -U tinbase --auth=trust >"$dir/initdb.log"
    # A random high port; another one when it is taken. Durability is not what the tests check
    # here (the crash tests kill tinbase, not the server).
    started=""
    for _ in 1 2 3 4 5 6 7 8 9 10; do
      port=$((20000 + RANDOM % 40000))
      if "${as_pg[@]}" "$pgbin/pg_ctl" -D "$dir/data" -l "$dir/server.log" -w \
        -o "-p $port -c listen_addresses=127.0.0.1 -k $dir -c fsync=off -c synchronous_commit=off \
            -c full_page_writes=off -c max_connections=200 -c jit=off" start >/dev/null; then
        started=yes
        break
      fi
    done
    [ -n "$started" ] || { echo "pg-server: the server did not start (see $dir/server.log)" >&2; exit 1; }
    "$pgbin/psql" -h 127.0.0.1 -p "$port" -U tinbase -d postgres -v ON_ERROR_STOP=1 -qAt \
      -c "CREATE DATABASE tinbase" >/dev/null
    "$pgbin/psql" -h 127.0.0.1 -p "$port" -U tinbase -d tinbase -v ON_ERROR_STOP=1 -qAt \
      -c "CREATE EXTENSION postgis" >/dev/null
    url="postgresql://tinbase@127.0.0.1:$port/tinbase"
    echo "$url" >"$dir/url"
    echo "$url"
    ;;
  stop)
    if [ -d "$dir/data" ]; then
      "${as_pg[@]}" "$pgbin/pg_ctl" -D "$dir/data" -m immediate stop >/dev/null 2>&1 || true
    fi
    rm -rf "$dir"
    ;;
  *) echo "usage: scripts/pg-server.sh start|stop DIR" >&2; exit 2 ;;
esac
