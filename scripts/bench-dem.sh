#!/usr/bin/env bash
# Issue 3's benchmark: the DEM store against GDAL on a tiled ZSTD (predictor 3) GeoTIFF, on a
# generated 8192 x 8192 terrain and the real SRTM tile. Usage: scripts/bench-dem.sh [OUTDIR]
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-build-bench/dem}
mkdir -p "$out"
cmake -S . -B build-bench -G Ninja -DCMAKE_BUILD_TYPE=Release -DTINBASE_BUILD_BENCH=ON >/dev/null
ninja -C build-bench dem_bench tinbase >/dev/null
build-bench/bench/dem_bench --size 8192 --dir "$out/generated-8192"
build-bench/bench/dem_bench --real tests/data/dem/N43E007.hgt --dir "$out/srtm-N43E007"
