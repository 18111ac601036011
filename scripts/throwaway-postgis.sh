# shellcheck shell=bash
# Sourced by the benchmark scripts that compare with PostGIS: a throwaway PostgreSQL 15 + PostGIS 3
# cluster (Debian postgresql-15, postgresql-15-postgis-3) in a temporary directory on a free
# loopback port, without JIT (its compile time is per statement, not per query) and without
# parallel workers (one core per client), stopped and removed when the script exits.
#
#   . scripts/throwaway-postgis.sh
#   pg_start                 # sets pg_port, pg_data and the array psql (-qAt, ON_ERROR_STOP)
#   "${psql[@]}" -c 'SELECT postgis_full_version()'
#   pg_bench_run ARGS...     # pgbench against the cluster's postgres database
# pg_start installs an EXIT trap that stops the cluster; a script with its own EXIT trap calls
# pg_stop from it.

pg_bin=/usr/lib/postgresql/15/bin

pg_check_installed() {
  [ -x "$pg_bin/initdb" ] || {
    echo "PostgreSQL 15 is missing: apt-get install postgresql-15 postgresql-15-postgis-3" >&2
    return 1
  }
  [ -f /usr/share/postgresql/15/extension/postgis.control ] || {
    echo "PostGIS for PostgreSQL 15 is missing: apt-get install postgresql-15-postgis-3" >&2
    return 1
  }
}

free_loopback_port() {
  python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0))
print(s.getsockname()[1])'
}

pg_stop() {
  [ -n "${pg_data:-}" ] || return 0
  "${pg_as_user[@]}" "$pg_bin/pg_ctl" -D "$pg_data" -m fast stop >/dev/null 2>&1 || true
  rm -rf "$pg_data"
  pg_data=
}

pg_start() {
  pg_check_installed
  pg_data=$(mktemp -d /tmp/tinbase-pg.XXXXXX)
  # initdb refuses to run as root, so the server then runs as the postgres user.
  pg_as_user=()
  if [ "$(id -u)" = 0 ]; then chown postgres "$pg_data"; pg_as_user=(runuser -u postgres --); fi
  pg_port=$(free_loopback_port)
  trap pg_stop EXIT
  "${pg_as_user[@]}" "$pg_bin/initdb" -D "$pg_data" -U bench --auth=trust >/dev/null
  "${pg_as_user[@]}" "$pg_bin/pg_ctl" -D "$pg_data" -l "$pg_data/server.log" -w \
    -o "-p $pg_port -c listen_addresses=127.0.0.1 -k $pg_data -c shared_buffers=1GB -c fsync=off \
        -c max_parallel_workers_per_gather=0 -c jit=off" start >/dev/null
  # shellcheck disable=SC2034  # for the sourcing script
  psql=("$pg_bin/psql" -h 127.0.0.1 -p "$pg_port" -U bench -d postgres -v ON_ERROR_STOP=1 -qAt)
}

pg_bench_run() {
  "$pg_bin/pgbench" -h 127.0.0.1 -p "$pg_port" -U bench "$@" postgres
}
