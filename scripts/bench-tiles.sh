#!/usr/bin/env bash
# Issue 25's tile benchmark: a full quantized-mesh pyramid of the bundled SRTM sheet N43E007 (and
# of a generated 4097^2 terrain): time, tiles, bytes and peak memory (with the default window and
# with windows of 16384 triangles); then a 1 km^2 polygon edit and `tiles update` against a full
# rebuild of the edited surface, with the tiles rewritten against those whose bounds meet the
# change and where the update's time went; then one tile made on demand at the finest level and
# at level 8, at the edit (the finest one the fastest of 5 in one process). Usage: scripts/bench-tiles.sh [OUTDIR] (default build-bench/tiles).
# Prints one table row per case and a line of the update's parts. TINBASE_BENCH_BUILD names a
# Release build directory to use instead of configuring build-bench.
#
# The peer, with CTB_TILE=/path/to/ctb-tile: cesium-terrain-builder's quantized-mesh fork,
# alternated with tinbase on the same DEMs (PEER_ROUNDS rounds, default 2): ctb-tile -f Mesh -N
# from the DEM against tinbase's `tiles build --extensions octvertexnormals` from its stored TIN,
# and against the whole of tinbase's way from the DEM (dem import, tin build at 5 m, tiles
# build); wall time, peak RSS, tiles, bytes, triangles, and the crack count of both pyramids
# (neighbours at one level: shared-edge vertices that one side lacks, and shared ones whose heights
# differ by more than the two tiles' quantisation half-steps). ONLY=peers skips the cases above.
# ctb-tile is not packaged; build it under /tmp (nothing of it goes into this repository):
#   git clone -b master-quantized-mesh https://github.com/ahuarte47/cesium-terrain-builder ctb
#   # GDAL 3.6 (Debian 12) changed two virtuals of the GDAL-internal copy it compiles in:
#   sed -i -e 's/RefUnderlyingRasterBand() override/RefUnderlyingRasterBand() const override/' \
#     -e 's/^GDALRasterBand\* GDALOverviewBand::RefUnderlyingRasterBand()$/& const/' \
#     -e 's/^    CPLErr FlushCache() override;/    CPLErr FlushCache(bool bAtClosing) override;/' \
#     -e 's/^CPLErr GDALOverviewBand::FlushCache()$/CPLErr GDALOverviewBand::FlushCache(bool bAtClosing)/' \
#     -e 's/poUnderlyingBand->FlushCache();/poUnderlyingBand->FlushCache(bAtClosing);/' \
#     -e 's/::FlushCache();/::FlushCache(true);/' ctb/src/gdaloverviewdataset.cpp
#   cmake -S ctb -B ctb/build -DCMAKE_BUILD_TYPE=Release && make -C ctb/build ctb-tile
#   (libgdal-dev, cmake and zlib1g-dev from Debian); the binary is ctb/build/tools/ctb-tile.
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

# The quantized-mesh tiles under DIR (gzipped or not), read by the format's layout: "tiles bytes
# triangles pairs unmatched heights_apart" (bytes unzipped; pairs: neighbours at one level).
cat >"$out/qm_stats.py" <<'PY'
import gzip, os, struct, sys
from collections import defaultdict

def decode(data):
    min_h, max_h = struct.unpack_from("<ff", data, 24)
    (n,) = struct.unpack_from("<I", data, 88)
    def unzigzag(off):
        vals, acc = [], 0
        for (d,) in struct.iter_unpack("<H", data[off:off + 2 * n]):
            acc += (d >> 1) ^ -(d & 1)
            vals.append(acc)
        return vals
    u, v, h = unzigzag(92), unzigzag(92 + 2 * n), unzigzag(92 + 4 * n)
    off = 92 + 6 * n
    align = 4 if n > 65536 else 2
    off += -off % align
    return min_h, max_h, u, v, h, struct.unpack_from("<I", data, off)[0]

tiles, raw, triangles, edges = 0, 0, 0, {}
for dirpath, _, files in os.walk(sys.argv[1]):
    for f in files:
        if not f.endswith(".terrain"):
            continue
        data = open(os.path.join(dirpath, f), "rb").read()
        if data[:2] == b"\x1f\x8b":
            data = gzip.decompress(data)
        z, x = (int(p) for p in dirpath.split(os.sep)[-2:])
        min_h, max_h, u, v, h, t = decode(data)
        tiles, raw, triangles = tiles + 1, raw + len(data), triangles + t
        step = (max_h - min_h) / 32767
        sides = defaultdict(dict)
        for a, b, c in zip(u, v, h):
            for side, on, along in (("w", a == 0, b), ("e", a == 32767, b), ("s", b == 0, a),
                                    ("n", b == 32767, a)):
                if on:
                    sides[side][along] = min_h + step * c
        edges[(z, x, int(f[:-8]))] = (sides, step)
pairs = unmatched = apart = 0
for (z, x, y), (sides, step) in edges.items():
    for dx, dy, mine, theirs in ((1, 0, "e", "w"), (0, 1, "n", "s")):
        other = edges.get((z, x + dx, y + dy))
        if other is None:
            continue
        pairs += 1
        a, b = sides[mine], other[0][theirs]
        unmatched += len(a.keys() ^ b.keys())
        apart += sum(abs(a[k] - b[k]) > (step + other[1]) / 2 + 1e-6 for k in a.keys() & b.keys())
print(tiles, raw, triangles, pairs, unmatched, apart)
PY

# name, DEM, max zoom: rounds alternating tinbase (from the DEM: import, tin build, tiles build)
# and ctb-tile (from the DEM), each timed by /usr/bin/time; one row per tool per round.
peer_case() {
  local round first
  for round in $(seq 1 "${PEER_ROUNDS:-2}"); do
    if [ $((round % 2)) = 1 ]; then first=tinbase; else first=ctb; fi
    for tool in $first $([ "$first" = tinbase ] && echo ctb || echo tinbase); do
      local dir="$out/peer-$1-$tool" t
      rm -rf "$dir" && mkdir -p "$dir"
      if [ "$tool" = ctb ]; then
        mkdir "$dir/tiles"
        /usr/bin/time -f "%e %M" -o "$dir/time" "$CTB_TILE" -q -f Mesh -N -s "$3" -e 0 \
          -o "$dir/tiles" "$2" >/dev/null 2>"$dir/log" || { cat "$dir/log" >&2; exit 1; }
        read -r t rss <"$dir/time"
        read -r tiles raw tris pairs unmatched apart < <(python3 "$out/qm_stats.py" "$dir/tiles")
        printf '| %s | %s | ctb-tile -f Mesh -N | %.1f | | %.0f | %s | %.2f | %.2f | %s | %s | %s | %s |\n' \
          "$1" "$round" "$t" "$((rss / 1024))" "$tiles" \
          "$(du -sb "$dir/tiles" | awk '{print $1 / 1048576}')" "$(echo "$raw / 1048576" | bc -l)" \
          "$tris" "$pairs" "$unmatched" "$apart"
      else
        local store="$dir/s.tinbase" start from_dem
        start=$(date +%s.%N)
        "$tinbase" init "$store" >/dev/null
        "$tinbase" dem import "$store" "$2" >/dev/null
        "$tinbase" tin build "$store" --surface t --tolerance 5 >/dev/null
        /usr/bin/time -f "%e %M" -o "$dir/time" "$tinbase" tiles build "$store" --surface t \
          --max-zoom "$3" --extensions octvertexnormals >/dev/null
        from_dem=$(echo "$(date +%s.%N) - $start" | bc -l)
        read -r t rss <"$dir/time"
        "$tinbase" tiles export "$store" --surface t -o "$dir/tiles" >/dev/null
        read -r tiles raw tris pairs unmatched apart < <(python3 "$out/qm_stats.py" "$dir/tiles")
        printf '| %s | %s | tinbase tiles build | %.1f | %.1f | %.0f | %s | %.2f | %.2f | %s | %s | %s | %s |\n' \
          "$1" "$round" "$t" "$from_dem" "$((rss / 1024))" "$tiles" \
          "$(du -sb "$dir/tiles" | awk '{print $1 / 1048576}')" "$(echo "$raw / 1048576" | bc -l)" \
          "$tris" "$pairs" "$unmatched" "$apart"
      fi
    done
  done
}

if [ "${ONLY:-}" != peers ]; then
  rm -f "$out/parts.txt"
  echo "| case | triangles | max zoom | tiles | MiB | peak RSS MiB | peak RSS MiB, 16384-triangle windows | build s | ms/tile | update s | rebuild s | rebuild/update | rewritten of meeting | finest tile on demand ms | level-8 tile on demand ms |"
  echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
  run_case srtm-N43E007-5m tests/data/dem/N43E007.hgt 5 12 0.5 0.9
  "$build"/bench/tin_bench export --size 4097 --out "$out/gen4097" >/dev/null
  run_case generated-4097-5m "$out/gen4097/terrain.tif" 5 15 0.4 0.4
  cat "$out/parts.txt"
fi

if [ -n "${CTB_TILE:-}" ]; then
  [ -x "$CTB_TILE" ] || { echo "CTB_TILE=$CTB_TILE is not an executable" >&2; exit 1; }
  [ -f "$out/gen4097/terrain.tif" ] ||
    "$build"/bench/tin_bench export --size 4097 --out "$out/gen4097" >/dev/null
  echo
  echo "| case | round | tool | tiles s | from the DEM s | peak RSS MiB | tiles | MiB on disk | MiB unzipped | triangles | neighbour pairs | unmatched edge vertices | edge heights apart |"
  echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|"
  peer_case srtm-N43E007 tests/data/dem/N43E007.hgt 12
  peer_case generated-4097 "$out/gen4097/terrain.tif" 15
fi
