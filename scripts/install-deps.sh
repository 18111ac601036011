#!/usr/bin/env bash
# Installs tinbase's build and test dependencies from Debian's packages (idempotent: does nothing
# when everything is already installed). Usage: scripts/install-deps.sh
set -euo pipefail

PACKAGES=(
  build-essential cmake ninja-build pkg-config
  libcgal-dev libgmp-dev libmpfr-dev libboost-dev
  libgdal-dev gdal-bin libgeographiclib-dev libgeos-dev
  libopenvdb-dev libboost-iostreams-dev
  libsqlite3-dev sqlite3 libblosc-dev libzstd-dev zlib1g-dev
  libpq-dev postgresql-15 postgresql-15-postgis-3
  postgresql-15-pgtap libtap-parser-sourcehandler-pgtap-perl
  postgresql-server-dev-15
  nlohmann-json3-dev libcli11-dev
  libtbb-dev
  libtinygltf-dev libmeshoptimizer-dev libcpp-httplib-dev
  nodejs
  chromium
  libgtest-dev libgmock-dev librapidcheck-dev libbenchmark-dev
  clang-format clang-tidy
  clang libclang-rt-14-dev
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
# The glTF validator of the tests runs on node with npm (scripts/install-test-tools.sh). Debian
# ships npm as its own package; NodeSource's nodejs bundles it, so only ask for it when absent.
command -v npm >/dev/null || missing+=(npm)
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#PACKAGES[@]} packages present"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "install-deps: run as root or install sudo" >&2; exit 1; }
  SUDO=sudo
fi
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
