#!/bin/sh
# Spatial reprojection with hole filling against full path tracing of every view (issue 13;
# docs/benchmarks.md, "Spatial reprojection"): Leria et al.'s Sponza fly-through (every
# 10th of its 100 frames: bench/sequences/sponza_flythrough_every10.json is the same
# keyframes at a tenth of the frame numbers), 1 spp, 8 bounces, 0.2 view spacing, grids
# 3x3, 5x5 and 9x9, on the heterogeneous pair of bench/leria.sh (one core at full speed,
# one emulated at half speed) with dlb; references: the centre alone (the paper), every
# 2nd and every 4th view from the centre (ours).
#   bench/reprojection.sh [BUILD] [RES]   (default build/, 320x180; needs ../shared/data)
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
res=${2:-320x180}
bin=$build/bench/reprojection_bench
scene=$root/../shared/data/meshes/dabrovic_sponza/sponza.obj
[ -x "$bin" ] || { echo "reprojection.sh: build $bin first"; exit 1; }
[ -f "$scene" ] || { echo "reprojection.sh: skipped: $scene not found"; exit 0; }
out=$root/bench-out/reprojection
mkdir -p "$out"
"$bin" "$scene" --res "$res" --spp 1 --bounces 8 --spacing 0.2 --grids 3x3,5x5,9x9 --reference-spacings 0,2,4 \
  --frames 10 --camera-path "$root/bench/sequences/sponza_flythrough_every10.json" \
  --json "$out/reprojection.json" --images "$out"
echo "reprojection.sh: wrote $out"
