#!/bin/sh
# Issue 30's goals on real devices: our default against every peer balancer on the pairs
# users have, each bench with `--repeats` blocks and intervals (docs/benchmarks.md).
#
#   pocl-sponza, pocl-helmet, pocl-default
#               the CPU device on core 0 against PoCL's basic driver on core 1 (a real
#               heterogeneous pair): Sponza, DamagedHelmet and the default scene
#   pair31      two pinned CPU threads, device 1 at an emulated third of the speed
#   pair31-perturbed
#               the same, device 1 halving its speed at frame 30 (emulated)
#
# Usage: bench/real_pairs.sh BUILD_DIR [OUT_DIR] [SET ...]   (default: every set)
# Environment: BALANCERS (comma-separated specs), REPEATS (3), FRAMES (60), TRACE (1: also
# write each balancer's trace, OUT_DIR/SET-<balancer>.trace, for `simulate --predict`).
# Run it on a quiet machine (no build, test or other job): each bench prints and records
# its own contention probe and says when its figures are not trustworthy.
set -eu
build=${1:?usage: bench/real_pairs.sh BUILD_DIR [OUT_DIR] [SET ...]}
out=${2:-/tmp/multiray_real_pairs}
shift $(($# >= 2 ? 2 : 1))
sets=${*:-pocl-sponza pocl-helmet pocl-default pair31 pair31-perturbed}
bin="$build/src/app/multiray"
root=$(cd "$(dirname "$0")/.." && pwd)
data="$root/../shared/data/meshes"
peers=cycles,equalizer,ospray-static,ospray-dynamic
ours=auto,hybrid,hybrid:taper=0.95
balancers=${BALANCERS:-$ours,queue,static,semi-static,dlb,uniform,$peers}
repeats=${REPEATS:-3}
frames=${FRAMES:-60}
mkdir -p "$out"

# one NAME ARGS...: one bench, its table and its probe.
one() {
  name=$1
  shift
  echo "== $name ($(date -u +%H:%M:%S), load $(cut -d' ' -f1-3 /proc/loadavg))"
  trace=""
  [ "${TRACE:-0}" = 1 ] && trace="--trace $out/$name"
  # shellcheck disable=SC2086 # $trace is empty or two words
  "$bin" bench "$@" --frames "$frames" --repeats "$repeats" --balancers "$balancers" $trace \
    --json "$out/$name.json" > "$out/$name.txt"
  grep -A 20 "^balancer " "$out/$name.txt" | tail -n +1 | head -n 16
}

# needs FILE: true when FILE exists, else a message (a clone without ../shared/ skips).
needs() {
  [ -f "$1" ] && return 0
  echo "skipping: $1 not found"
  return 1
}

export POCL_DEVICES=basic  # PoCL's one-core driver: a device of its own, beside the CPU device
pocl=cpu:threads=1:cores=0,opencl:0:cores=1
pair=cpu:threads=1:cores=0,cpu:threads=1:cores=1:speed=0.3333
for set in $sets; do
  case $set in
  pocl-sponza)
    f="$data/dabrovic_sponza/sponza.obj"
    needs "$f" && one "$set" "$f" --camera -10,3,0,10,5,0,0,1,0,60 \
      --res 640x360 --spp 1 --camera-path orbit --devices $pocl
    ;;
  pocl-helmet)
    f="$data/damaged_helmet/DamagedHelmet.gltf"
    needs "$f" && one "$set" "$f" --res 640x360 --spp 1 \
      --camera-path orbit --devices $pocl
    ;;
  pocl-default)
    one "$set" --res 320x180 --spp 4 --camera-path orbit --devices $pocl
    ;;
  pair31)
    one "$set" --res 640x360 --spp 2 --camera-path orbit --devices $pair
    ;;
  pair31-perturbed)
    one "$set" --res 640x360 --spp 2 --camera-path orbit --devices $pair \
      --perturb "$((frames / 2)):1:0.1667"
    ;;
  *)
    echo "unknown set '$set'" >&2
    exit 2
    ;;
  esac
done
