#!/bin/sh
# Balancers at scale on frames where scale means something (issue 30): Sponza traced at
# 3840x2160 and 7680x4320 (1 spp, real renders on one CPU core), replayed by `multiray
# simulate` on 2..1024 virtual devices behind the emulated LAN and Wi-Fi links, with results
# sent as plain floats (12 bytes a pixel) and as float+zstd (the default of distributed
# runs, lossless), every balancer, in virtual time.
#
# Usage: bench/scaling_large.sh BUILD_DIR [OUT_DIR]   (results in docs/benchmarks.md)
# Recording the traces takes a few minutes and needs a quiet machine (the traces' tile
# costs are measured); the simulations are virtual time and need no quiet.
# Environment: SIZES ("3840x2160:16 7680x4320:32": size and the queue's tile while
# recording), FRAMES (traced frames per size, 6), COUNTS, LINKS, ENCODINGS, SIM_FRAMES (40), RECORD_ONLY (1:
# record the traces, simulate nothing: the quiet part alone).
set -eu
build=${1:?usage: bench/scaling_large.sh BUILD_DIR [OUT_DIR]}
out=${2:-/tmp/multiray_scaling_large}
bin="$build/src/app/multiray"
root=$(cd "$(dirname "$0")/.." && pwd)
sponza="$root/../shared/data/meshes/dabrovic_sponza/sponza.obj"
sizes=${SIZES:-3840x2160:16 7680x4320:32}
frames=${FRAMES:-6}
counts=${COUNTS:-2,4,8,16,32,64,128,256,512,1024}
links=${LINKS:-lan wifi}
encodings=${ENCODINGS:-float float+zstd}
sim_frames=${SIM_FRAMES:-40}
if [ ! -f "$sponza" ]; then
  echo "skipping: $sponza not found"
  exit 0
fi
mkdir -p "$out"

for size in $sizes; do
  res=${size%%:*}
  tile=${size#*:}
  trace="$out/sponza-$res.trace"
  if [ ! -f "$trace" ]; then
    echo "== recording $res ($(date -u +%H:%M:%S), load $(cut -d' ' -f1-3 /proc/loadavg))"
    "$bin" render "$sponza" --camera -10,3,0,10,5,0,0,1,0,60 --res "$res" --spp 1 \
      --frames "$frames" --camera-path orbit:40 --devices cpu:threads=1 \
      --balancer "queue:tile=$tile" --trace "$trace" --out "$out/frames-$res" --overwrite -q
  fi
  [ "${RECORD_ONLY:-0}" = 1 ] && continue
  for link in $links; do
    for enc in $encodings; do
      name="sponza-$res-$link-$enc"
      echo "== simulating $name ($(date -u +%H:%M:%S))"
      "$bin" simulate "$trace" --devices "$counts" --speeds random:0.3 --noise 0.05 \
        --slowdown 20 --link "$link" --result-encoding "$enc" --frames "$sim_frames" --warmup "$((sim_frames / 6))" \
        --json "$out/$name.json" --plot "$out/$name.svg" > "$out/$name.txt"
    done
  done
done
# Per table: the largest device count at which each balancer stays at or above the goal
# (0.9 on the LAN, 0.8 on Wi-Fi).
[ "${RECORD_ONLY:-0}" = 1 ] && exit 0
python3 "$root/bench/scaling_reach.py" "$out"/sponza-*.json
