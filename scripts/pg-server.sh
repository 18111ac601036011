#!/usr/bin/env bash
# A throwaway PostgreSQL 15 with PostGIS for the tests, the benchmarks (scripts/throwaway-postgis.sh
# sources a wrapper of it) and anyone trying the PostgreSQL backend: a cluster initialised in DIR,
# on a free port of 127.0.0.1 only, with trust authentication for the local user `tinbase`, a
# database `tinbase` with PostGIS, nothing kept after `stop`. A role `tinbase_password`, if a
# test makes one, must log in with its password.
#   scripts/pg-server.sh start DIR [--extension-dir EXT] [-c NAME=VALUE ...]
#       starts it; prints its URL, also written to DIR/url. --extension-dir adds the extension
#       files of EXT (the build's extensions/postgresql/extension: CREATE EXTENSION tinbase), its
#       modules (*.so) to the server's $libdir;
#       -c sets a server setting.
#   scripts/pg-server.sh stop DIR    stops it and removes DIR
# Needs Debian's postgresql-15 and postgresql-15-postgis-3 (scripts/install-deps.sh).
#
# The server gets an installation tree of its own, DIR/root, so extensions can be added to it
# without touching the system's (PostgreSQL 15 reads extension files from its share directory
# only). PostgreSQL finds that directory from where its own binary is, relative to the bin
# directory it was built with: DIR/root/lib/postgresql/15/bin/postgres (a hard link to Debian's,
# a copy when the link cannot be made) finds DIR/root/share/postgresql/15, whose entries are
# links to Debian's but for extension/, which holds links to every system extension file and to
# the files of EXT; DIR/root/lib/postgresql/15/lib ($libdir) likewise links Debian's modules and
# those of EXT. initdb refuses to run as root, so as root the server runs as the postgres user.
set -euo pipefail
action=${1:-}
dir=${2:-}
usage="usage: scripts/pg-server.sh start DIR [--extension-dir EXT] [-c NAME=VALUE ...] | stop DIR"
if [ -z "$action" ] || [ -z "$dir" ]; then echo "$usage" >&2; exit 2; fi
shift 2
pgbin=/usr/lib/postgresql/15/bin
pgshare=/usr/share/postgresql/15
as_pg=()
[ "$(id -u)" = 0 ] && as_pg=(runuser -u postgres --)

# The private installation tree DIR/root described above, with the extension files of $1 if set.
make_root() {
  local root=$1/root ext=$2
  mkdir -p "$root/lib/postgresql/15/bin" "$root/share/postgresql/15/extension"
  ln "$pgbin/postgres" "$root/lib/postgresql/15/bin/postgres" 2>/dev/null ||
    cp "$pgbin/postgres" "$root/lib/postgresql/15/bin/postgres"
  local entry
  mkdir -p "$root/lib/postgresql/15/lib"
  for entry in /usr/lib/postgresql/15/lib/*; do ln -s "$entry" "$root/lib/postgresql/15/lib/"; done
  for entry in "$pgshare"/*; do
    [ "$(basename "$entry")" = extension ] || ln -s "$entry" "$root/share/postgresql/15/"
  done
  for entry in "$pgshare"/extension/*; do ln -s "$entry" "$root/share/postgresql/15/extension/"; done
  if [ -n "$ext" ]; then
    ls "$ext"/*.control >/dev/null 2>&1 ||
      { echo "pg-server: no extension (.control file) in $ext" >&2; return 1; }
    for entry in "$ext"/*; do
      case "$entry" in
        *.so) ln -sf "$(realpath "$entry")" "$root/lib/postgresql/15/lib/" ;;
        *) ln -sf "$(realpath "$entry")" "$root/share/postgresql/15/extension/" ;;
      esac
    done
  fi
}

case "$action" in
  start)
    ext=""
    settings=()
    while [ $# -gt 0 ]; do
      case "$1" in
        --extension-dir) ext=${2:?"--extension-dir needs a directory"}; shift 2 ;;
        -c) settings+=(-c "${2:?"-c needs NAME=VALUE"}"); shift 2 ;;
        *) echo "pg-server: unknown option '$1'; $usage" >&2; exit 2 ;;
      esac
    done
    [ -x "$pgbin/initdb" ] || { echo "pg-server: PostgreSQL 15 is missing (apt-get install postgresql-15)" >&2; exit 1; }
    [ -f "$pgshare/extension/postgis.control" ] ||
      { echo "pg-server: PostGIS is missing (apt-get install postgresql-15-postgis-3)" >&2; exit 1; }
    mkdir -p "$dir"
    dir=$(cd "$dir" && pwd)
    make_root "$dir" "$ext"
    [ "$(id -u)" = 0 ] && chown -R postgres "$dir"
    "${as_pg[@]}" "$pgbin/initdb" -D "$dir/data" -U tinbase --auth=trust >"$dir/initdb.log"
    # One role must give a password, so the tests can try a wrong one (the first matching line
    # of pg_hba.conf wins; everyone else is trusted).
    { echo "host all tinbase_password 127.0.0.1/32 scram-sha-256"; cat "$dir/data/pg_hba.conf"; } \
      >"$dir/pg_hba.conf"
    "${as_pg[@]}" cp "$dir/pg_hba.conf" "$dir/data/pg_hba.conf"
    # A random high port; another one when it is taken. Durability is not what the tests check
    # here (the crash tests kill tinbase, not the server).
    started=""
    for _ in 1 2 3 4 5 6 7 8 9 10; do
      port=$((20000 + RANDOM % 40000))
      if "${as_pg[@]}" "$pgbin/pg_ctl" -D "$dir/data" -p "$dir/root/lib/postgresql/15/bin/postgres" \
        -l "$dir/server.log" -w -o "-p $port -c listen_addresses=127.0.0.1 -k $dir -c fsync=off \
            -c synchronous_commit=off -c full_page_writes=off -c max_connections=200 -c jit=off \
            ${settings[*]}" start >/dev/null; then
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
  *) echo "$usage" >&2; exit 2 ;;
esac
