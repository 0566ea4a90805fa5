#!/bin/sh
# Bruder et al. 2017's experiments on our volumes (docs/benchmarks.md, "Volumes"):
# frame-time targeting modes on a 300-frame sequence with two transfer-function switches,
# and prediction-based balancing against static and the others.
#   bench/volume_targeting.sh BUILD OUT [FRAMES] [PARTS]
#   PARTS: any of "targeting targeting-opencl balance" (default: all three)
# Needs ../shared/data/volumes. Two emulated CPU devices 1 : 0.4 (one thread each) and a
# CPU + OpenCL (PoCL) pair (set POCL_MAX_PTHREAD_COUNT=1 so that it fits two cores).
set -eu
build=${1:-build}
out=${2:-bench-out/volumes}
frames=${3:-300}
parts=${4:-"targeting targeting-opencl balance"}
data="$(dirname "$0")/../../shared/data/volumes"
seqs="$(dirname "$0")/sequences"
mkdir -p "$out"
for vol in aneurism cranium; do
  case $vol in
    aneurism) file="$data/aneurism_256x256x256_uint8.nhdr" ;;
    cranium) file="$data/cranium_ct_256x256x108_int16le.nhdr" ;;
  esac
  # Targeting: each mode with the balancer we recommend for volumes.
  case " $parts " in *" targeting "*)
  "$build/src/app/multiray" bench "$file" --res 256x192 --frames "$frames" --warmup 10 \
    --ideal-frames 10 --sequence "$seqs/$vol.json" --target-ms 100 \
    --adapt none,last-frame,two-pass,predict,predict:q=0.9 --balancers bruder:zeta=0:steal=1 \
    --devices cpu:threads=1,cpu:threads=1:speed=0.4 \
    --json "$out/$vol-targeting.json" --report "$out/$vol-targeting" > "$out/$vol-targeting.txt"
  ;; esac
  # Targeting on the real heterogeneous pair: one CPU thread + one PoCL device.
  case $parts in *targeting-opencl*)
  "$build/src/app/multiray" bench "$file" --res 256x192 --frames "$frames" --warmup 10 \
    --ideal-frames 10 --sequence "$seqs/$vol.json" --target-ms 100 \
    --adapt none,last-frame,two-pass,predict,predict:q=0.9 --balancers bruder:zeta=0:steal=1 \
    --devices cpu:threads=1,opencl \
    --json "$out/$vol-targeting-opencl.json" --report "$out/$vol-targeting-opencl" \
    > "$out/$vol-targeting-opencl.txt"
  ;; esac
  # Balancing: full quality, prediction-based shares against static and the others.
  case $parts in *balance*)
  "$build/src/app/multiray" bench "$file" --res 256x192 --frames 100 --warmup 10 \
    --ideal-frames 10 --sequence "$seqs/$vol.json" --adapt none \
    --balancers static,bruder,bruder:zeta=0,bruder:zeta=0:steal=1,hybrid,queue \
    --devices cpu:threads=1,opencl --json "$out/$vol-balance.json" \
    > "$out/$vol-balance.txt"
  ;; esac
done
