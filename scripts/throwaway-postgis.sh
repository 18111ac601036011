# shellcheck shell=bash
# Sourced by the benchmark scripts that compare with PostGIS: the throwaway PostgreSQL 15 +
# PostGIS 3 server of scripts/pg-server.sh (Debian postgresql-15, postgresql-15-postgis-3) in a
# temporary directory on a free loopback port, here also without parallel workers (one core per
# client) and with 1 GB of shared buffers, stopped and removed when the script exits. (JIT is off
# there already: its compile time is per statement, not per query.)
#
#   . scripts/throwaway-postgis.sh
#   pg_start                 # sets pg_port, pg_data and the array psql (-qAt, ON_ERROR_STOP)
#   "${psql[@]}" -c 'SELECT postgis_full_version()'
#   pg_bench_run ARGS...     # pgbench against the cluster's postgres database
# psql and pgbench use the database `postgres`, where nothing is installed (CREATE EXTENSION
# postgis there first); pg-server.sh's own database `tinbase` has PostGIS. pg_start installs an
# EXIT trap that stops the cluster; a script with its own EXIT trap calls pg_stop from it.

pg_bin=/usr/lib/postgresql/15/bin
pg_server_script=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)/pg-server.sh

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

pg_stop() {
  [ -n "${pg_dir:-}" ] || return 0
  "$pg_server_script" stop "$pg_dir"
  pg_dir=
  pg_data=
}

pg_start() {
  pg_check_installed
  pg_dir=$(mktemp -d /tmp/tinbase-pg.XXXXXX)
  trap pg_stop EXIT
  local url
  url=$("$pg_server_script" start "$pg_dir" -c shared_buffers=1GB \
    -c max_parallel_workers_per_gather=0)
  pg_port=${url##*:}
  pg_port=${pg_port%%/*}
  # shellcheck disable=SC2034  # for the sourcing script
  pg_data=$pg_dir/data  # holds postmaster.pid
  # shellcheck disable=SC2034
  psql=("$pg_bin/psql" -h 127.0.0.1 -p "$pg_port" -U tinbase -d postgres -v ON_ERROR_STOP=1 -qAt)
}

pg_bench_run() {
  "$pg_bin/pgbench" -h 127.0.0.1 -p "$pg_port" -U tinbase "$@" postgres
}
