#!/usr/bin/env bash
# Issue 25's tile benchmark: a full quantized-mesh pyramid of the bundled SRTM sheet N43E007 (and
# of a generated 4097^2 terrain): time, tiles, bytes and peak memory (with the default window and
# with windows of 16384 triangles); then a 1 km^2 polygon edit and `tiles update` against a full
# rebuild of the edited surface, with the tiles rewritten against those whose bounds meet the
# change and where the update's time went; then one tile made on demand at the finest level and
# at level 8, at the edit (the finest one the fastest of 5 in one process). Usage: scripts/bench-tiles.sh [OUTDIR] (default build-bench/tiles).
# Prints one table row per case and a line of the update's parts. TINBASE_BENCH_BUILD names a
# Release build directory to use instead of configuring build-bench.
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-build-bench/tiles}
mkdir -p "$out"
build=${TINBASE_BENCH_BUILD:-build-bench}
if [ -z "${TINBASE_BENCH_BUILD:-}" ]; then
  cmake -S . -B build-bench -G Ninja -DCMAKE_BUILD_TYPE=Release -DTINBASE_BUILD_BENCH=ON >/dev/null
fi
ninja -C "$build" tinbase tin_bench >/dev/null
tinbase=$build/apps/tinbase
json() { python3 -c "import json,sys; print(json.load(sys.stdin)$1)"; }
peak_mib() { sed -n 's/.*Maximum resident set size (kbytes): \([0-9]*\).*/\1/p' "$1" | awk '{printf "%.0f", $1/1024}'; }

# name, DEM file, tolerance, max zoom, where the edit goes (fractions of the DEM's box)
run_case() {
  local store="$out/$1.tinbase"
  rm -f "$store" "$store"-*
  "$tinbase" init "$store" >/dev/null
  "$tinbase" dem import "$store" "$2" >/dev/null
  "$tinbase" tin build "$store" --surface t --tolerance "$3" >/dev/null
  local triangles
  triangles=$("$tinbase" info --json "$store" | json "['surfaces'][0]['triangles']")
  /usr/bin/time -v "$tinbase" tiles build "$store" --surface t --max-zoom "$4" \
    --extensions octvertexnormals,metadata --json >"$out/$1.build.json" 2>"$out/$1.build.time"
  /usr/bin/time -v "$tinbase" tiles build "$store" --surface t --max-zoom "$4" \
    --extensions octvertexnormals,metadata --window-triangles 16384 --json \
    >"$out/$1.small.json" 2>"$out/$1.small.time"
  local build_s tiles bytes
  build_s=$(json "['seconds']" <"$out/$1.build.json")
  tiles=$(json "['tiles']" <"$out/$1.build.json")
  bytes=$(json "['bytes']" <"$out/$1.build.json")
  # A 1 km square (smaller on a small DEM), erased.
  read -r crs x y side < <("$tinbase" info --json "$store" | python3 -c "
import json,sys; j=json.load(sys.stdin); b=j['dems'][0]['bbox']
print(j['crs'], b[0]+$5*(b[2]-b[0]), b[1]+$6*(b[3]-b[1]), min(1000, 0.05*(b[2]-b[0])))")
  python3 - "$out/square.geojson" "$crs" "$x" "$y" "$side" <<'PY'
import json, sys
path, crs = sys.argv[1], sys.argv[2]
x, y, d = float(sys.argv[3]), float(sys.argv[4]), float(sys.argv[5])
ring = [[x, y], [x + d, y], [x + d, y + d], [x, y + d], [x, y]]
json.dump({"type": "FeatureCollection", "crs": {"type": "name", "properties": {"name": crs}},
           "features": [{"type": "Feature", "properties": {},
                         "geometry": {"type": "Polygon", "coordinates": [ring]}}]}, open(path, "w"))
PY
  "$tinbase" polygon add "$store" "$out/square.geojson" --surface t --mode erase >/dev/null
  "$tinbase" tiles update "$store" --surface t --json >"$out/$1.update.json"
  local update_s rewritten meeting
  update_s=$(json "['seconds']" <"$out/$1.update.json")
  rewritten=$(json "['tiles_rewritten']" <"$out/$1.update.json")
  meeting=$(json "['tiles_meeting']" <"$out/$1.update.json")
  local rebuild_s
  rebuild_s=$("$tinbase" tiles build "$store" --surface t --max-zoom "$4" \
    --extensions octvertexnormals,metadata --json | json "['seconds']")
  # One tile on demand at the edit's corner: the finest level's and level 8's.
  local lon lat fine mid fine_s mid_s
  read -r lon lat _ < <(echo "$x $y" | gdaltransform -s_srs "$crs" -t_srs EPSG:4326 -output_xy)
  fine=$(python3 -c "import math; z=$4; d=180/2**z; print(f'{z}/{math.floor(($lon+180)/d)}/{math.floor(($lat+90)/d)}')")
  mid=$(python3 -c "import math; z=8; d=180/2**z; print(f'{z}/{math.floor(($lon+180)/d)}/{math.floor(($lat+90)/d)}')")
  fine_s=$("$tinbase" tiles make "$store" --surface t --tile "$fine" --repeat 5 --json |
    json "['seconds']")
  mid_s=$("$tinbase" tiles make "$store" --surface t --tile "$mid" --json | json "['seconds']")
  printf '| %s | %s | %s | %s | %.2f | %s | %s | %.2f | %s | %.3f | %.2f | %.0fx | %s of %s | %.0f | %.0f |\n' \
    "$1" "$triangles" "$4" "$tiles" "$(echo "$bytes / 1048576" | bc -l)" \
    "$(peak_mib "$out/$1.build.time")" "$(peak_mib "$out/$1.small.time")" "$build_s" \
    "$(echo "$build_s * 1000 / $tiles" | bc -l | xargs printf '%.1f')" "$update_s" "$rebuild_s" \
    "$(echo "$rebuild_s / $update_s" | bc -l)" "$rewritten" "$meeting" \
    "$(echo "$fine_s * 1000" | bc -l)" "$(echo "$mid_s * 1000" | bc -l)"
  python3 - "$out/$1.update.json" "$1" <<'PY' >>"$out/parts.txt"
import json, sys
u = json.load(open(sys.argv[1]))
print(f"{sys.argv[2]}: update read {u['read_seconds']:.3f} s, cut and merge {u['make_seconds']:.3f} s,"
      f" write {u['write_seconds']:.3f} s")
PY
}

rm -f "$out/parts.txt"
echo "| case | triangles | max zoom | tiles | MiB | peak RSS MiB | peak RSS MiB, 16384-triangle windows | build s | ms/tile | update s | rebuild s | rebuild/update | rewritten of meeting | finest tile on demand ms | level-8 tile on demand ms |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
run_case srtm-N43E007-5m tests/data/dem/N43E007.hgt 5 12 0.5 0.9
"$build"/bench/tin_bench export --size 4097 --out "$out/gen4097" >/dev/null
run_case generated-4097-5m "$out/gen4097/terrain.tif" 5 15 0.4 0.4
cat "$out/parts.txt"
