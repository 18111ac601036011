#!/usr/bin/env bash
# Issue 4's side-by-side benchmark: tinbase's TIN builders against npm delatin and @mapbox/martini
# on generated terrains and a real SRTM window, bulk Delaunay against CGAL alone, and the error vs
# triangles plot. Usage: scripts/bench-tin.sh [OUTDIR] (default build-bench/tin). Needs node + npm.
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-build-bench/tin}
mkdir -p "$out"
command -v gnuplot >/dev/null || { echo "installing gnuplot-nox for the plot"; \
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends gnuplot-nox >/dev/null; }
(cd bench/peers && npm ci --no-audit --no-fund --silent)
cmake -S . -B build-bench -G Ninja -DCMAKE_BUILD_TYPE=Release -DTINBASE_BUILD_BENCH=ON >/dev/null
ninja -C build-bench tin_bench >/dev/null
bench=build-bench/bench/tin_bench

run_case() {  # name, export args, errors, measure flags
  local dir="$out/$1"
  "$bench" export $2 --out "$dir"
  local w h
  w=$(sed 's/.*"width":\([0-9]*\).*/\1/' "$dir/terrain.json")
  h=$(sed 's/.*"height":\([0-9]*\).*/\1/' "$dir/terrain.json")
  node bench/peers/run_peers.mjs "$dir/terrain.f32" "$w" "$h" "$dir" "$3" > "$dir/peers.jsonl"
  echo "### $1 ($w x $h)"
  "$bench" measure --dir "$dir" --errors "$3" $4
}

run_case generated-1025 "--size 1025" 0.5,1,5,20 --store
run_case generated-2049 "--size 2049" 0.5,1,5,20 --store
run_case generated-4097 "--size 4097" 1,5,20 --store
run_case srtm-N43E007-1025 "--real tests/data/dem/N43E007.hgt --size 1025" 0.5,1,5,20 --store
run_case plot-N43E007-513 "--real tests/data/dem/N43E007.hgt --size 513" 1,2,5,10,20,50 --all

echo "### bulk Delaunay: points | CGAL pts/s | tinbase to store pts/s | ratio | store bytes/pt | peak RSS MiB"
for n in 1000000 4000000 10000000; do "$bench" delaunay --points $n --dir "$out/delaunay"; done

plot="$out/plot-N43E007-513/results.csv"
gnuplot <<GP
set terminal pngcairo size 900,600 noenhanced
set output 'docs/tin_error_vs_triangles.png'
set datafile separator ','
set logscale xy
set xlabel 'triangles'
set ylabel 'true max |TIN - DEM| (m)'
set title 'SRTM N43E007, 513 x 513 window: error against size, every method and peer'
set key outside right
set grid
# One series per method, read through grep so each is drawn as a connected line; greedy last,
# over delatin, whose curve it matches.
plot for [m in "delatin martini rtin collapse vip greedy"] '< grep "^'.m.'," $plot' using 3:4 with linespoints lw 2 title m
GP
echo "plot: docs/tin_error_vs_triangles.png"
