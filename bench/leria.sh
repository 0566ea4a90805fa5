#!/bin/sh
# Leria et al.'s multiview experiments re-run on CPU devices (issue 13; docs/benchmarks.md,
# "Multiview DLB as in Leria et al."): a Sponza fly-through from above the roof into the
# courtyard (bench/sequences/sponza_flythrough.json), 1 spp, 8 bounces, 0.2 view spacing.
#   1. 3x3 views, 100 frames, dlb against its baseline on a heterogeneous pair (one core at
#      full speed, one emulated at half speed: labelled emulated in the output);
#   2. grids 2x1, 3x3, 5x5 and 9x9 on that pair, 30 frames (9x9: 12);
#   3. a homogeneous pair (two one-thread devices), where dlb must never rebalance
#      (the `rebalances` of the JSON summaries);
#   4. the paper's §6.3 Tables 1-2 setting: the homogeneous pair, 9x9 views, spatial
#      reprojection from the centre view (`--sampling reproject`), path-tracing time with
#      and without dlb (12 frames).
# PARTS (default 1234) picks the parts, GRIDS (default "2x1 3x3 5x5 9x9") part 2's grids,
# LANES (default below) the balancers. PAIR replaces parts 1-2's emulated pair and PAIR4
# part 4's homogeneous one, e.g. with a pair whose ratio we do not choose:
#   POCL_DEVICES=basic PAIR4=cpu:threads=1:cores=0,opencl:0:cores=1 PARTS=4 bench/leria.sh
# where Leria et al.'s ±10% check can fire (issue 54, item 1); FRAMES4 (default 12) sets
# part 4's frames (the paper's tables: 100).
# The baseline is Leria et al.'s: equal ratios over the same shuffled strips
# (`uniform:layout=strips`, which cuts exactly dlb's strips); `uniform` (two row bands, no
# per-strip cost) runs beside it as an extra lane. Every run repeats REPEATS blocks (3)
# and reports medians with 95% intervals.
#   bench/leria.sh [BUILD] [RES] [FRAMES]
#   (default build/, 320x180, 100 frames for part 1; the paper's size is 1280x720, about
#   16x the time; needs ../shared/data)
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
res=${2:-320x180}
fly_frames=${3:-100}
repeats=${REPEATS:-3}
parts=${PARTS:-1234}
lanes=${LANES:-uniform:layout=strips,dlb,uniform}
grids=${GRIDS:-2x1 3x3 5x5 9x9}
bin=$build/src/app/multiray
scene=$root/../shared/data/meshes/dabrovic_sponza/sponza.obj
path=$root/bench/sequences/sponza_flythrough.json
[ -x "$bin" ] || { echo "leria.sh: build $bin first"; exit 1; }
[ -f "$scene" ] || { echo "leria.sh: skipped: $scene not found"; exit 0; }
out=$root/bench-out/leria
mkdir -p "$out"
pair=${PAIR:-cpu:threads=1:cores=0,cpu:threads=1:cores=1:speed=0.5}
common="--res $res --spp 1 --bounces 8 --view-spacing 0.2 --camera-path $path --repeats $repeats"
homogeneous=cpu:threads=1:cores=0,cpu:threads=1:cores=1
pair4=${PAIR4:-$homogeneous}
frames4=${FRAMES4:-12}
part() { case "$parts" in *"$1"*) return 0 ;; esac; return 1; }
part 1 && "$bin" bench "$scene" $common --views 3x3 --frames "$fly_frames" --devices "$pair" \
  --balancers $lanes --json "$out/flythrough.json" --report "$out/flythrough"
part 2 && for grid in $grids; do
  frames=30 ideal=20
  [ "$grid" = 9x9 ] && frames=12 ideal=4  # 81 views: ~7 s a frame here
  "$bin" bench "$scene" $common --views "$grid" --frames $frames --ideal-frames $ideal \
    --devices "$pair" --balancers $lanes --json "$out/grid_$grid.json"
done
part 3 && "$bin" bench "$scene" $common --views 3x3 --frames 60 \
  --devices $homogeneous --balancers $lanes --json "$out/homogeneous.json"
part 4 && "$bin" bench "$scene" $common --views 9x9 --sampling reproject --frames "$frames4" \
  --ideal-frames 4 --devices "$pair4" --balancers uniform:layout=strips,dlb \
  --json "$out/tables_1_2.json"
echo "leria.sh: wrote $out"
