#!/bin/sh
# Leria et al.'s multiview experiments re-run on CPU devices (issue 13; docs/benchmarks.md,
# "Multiview DLB as in Leria et al."): a Sponza fly-through from above the roof into the
# courtyard (bench/sequences/sponza_flythrough.json), 1 spp, 8 bounces, 0.2 view spacing.
#   1. 3x3 views, 100 frames, uniform against dlb on a heterogeneous pair (one core at full
#      speed, one emulated at half speed: labelled emulated in the output);
#   2. grids 2x1, 3x3, 5x5 and 9x9 on that pair, 30 frames (9x9: 12);
#   3. a homogeneous pair (two one-thread devices), where dlb must never rebalance
#      (the `rebalances` of the JSON summaries).
#   bench/leria.sh [BUILD] [RES]   (default build/, 320x180; needs ../shared/data)
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
res=${2:-320x180}
bin=$build/src/app/multiray
scene=$root/../shared/data/meshes/dabrovic_sponza/sponza.obj
path=$root/bench/sequences/sponza_flythrough.json
[ -x "$bin" ] || { echo "leria.sh: build $bin first"; exit 1; }
[ -f "$scene" ] || { echo "leria.sh: skipped: $scene not found"; exit 0; }
out=$root/bench-out/leria
mkdir -p "$out"
pair=cpu:threads=1:cores=0,cpu:threads=1:cores=1:speed=0.5
common="--res $res --spp 1 --bounces 8 --view-spacing 0.2 --camera-path $path"
"$bin" bench "$scene" $common --views 3x3 --frames 100 --devices "$pair" \
  --balancers uniform,dlb --json "$out/flythrough.json" --report "$out/flythrough"
for grid in 2x1 3x3 5x5 9x9; do
  frames=30 ideal=20
  [ "$grid" = 9x9 ] && frames=12 ideal=4  # 81 views: ~7 s a frame here
  "$bin" bench "$scene" $common --views "$grid" --frames $frames --ideal-frames $ideal \
    --devices "$pair" --balancers uniform,dlb --json "$out/grid_$grid.json"
done
"$bin" bench "$scene" $common --views 3x3 --frames 60 \
  --devices cpu:threads=1:cores=0,cpu:threads=1:cores=1 --balancers uniform,dlb \
  --json "$out/homogeneous.json"
echo "leria.sh: wrote $out"
