#!/bin/sh
# Issue 27's check that the bench's verdict survives a rerun: each comparison is run twice,
# back to back, with `--repeats 3`, and bench/agree.py checks that every pair of balancers
# whose intervals separate in one run keeps its order in the other.
#
#   pair31     two CPU devices, one pinned thread each, device 1 at an emulated third of
#              the speed (the "3:1" pair), default scene and Sponza at 640x360
#   pocl       the CPU device on core 0 against PoCL's basic driver on core 1 (a real
#              heterogeneous pair), default scene and Sponza at 320x180, 4 spp
#
# Usage: bench/verdict_rerun.sh BUILD_DIR [OUT_DIR] [pair31|pocl ...]
# Run it on a quiet machine (no build, test or other job): each bench prints and records
# its own contention probe and says when its figures are not trustworthy.
set -eu
build=${1:?usage: bench/verdict_rerun.sh BUILD_DIR [OUT_DIR] [pair31|pocl ...]}
out=${2:-/tmp/multiray_verdict}
shift $(( $# >= 2 ? 2 : 1 ))
sets=${*:-pair31 pocl}
bin="$build/src/app/multiray"
root=$(cd "$(dirname "$0")/.." && pwd)
sponza="$root/../shared/data/meshes/dabrovic_sponza/sponza.obj"
mkdir -p "$out"

# twice NAME ARGS...: the bench twice, back to back, then the agreement check.
twice() {
  name=$1
  shift
  for k in 1 2; do
    echo "== $name, run $k ($(date -u +%H:%M:%S), load $(cut -d' ' -f1-3 /proc/loadavg))"
    "$bin" bench "$@" --repeats 3 --json "$out/$name-$k.json" > "$out/$name-$k.txt"
    tail -n 12 "$out/$name-$k.txt"
  done
  python3 "$root/bench/agree.py" "$out/$name-1.json" "$out/$name-2.json" | tee "$out/$name-agree.md"
}

for set in $sets; do
  case $set in
  pair31)
    d=cpu:threads=1:cores=0,cpu:threads=1:cores=1:speed=0.3333
    b=uniform,static,queue,semi-static,dlb,hybrid
    twice pair31-default --res 640x360 --spp 2 --frames 100 --devices $d --balancers $b
    if [ -f "$sponza" ]; then
      twice pair31-sponza "$sponza" --camera -10,3,0,10,5,0,0,1,0,60 --res 640x360 --spp 1 \
        --frames 100 --devices $d --balancers $b
    else
      echo "skipping Sponza: $sponza not found"
    fi
    ;;
  pocl)
    export POCL_DEVICES=basic
    d=cpu:threads=1:cores=0,opencl:0:cores=1
    twice pocl-default --res 320x180 --spp 4 --frames 30 --camera-path fixed --devices $d
    if [ -f "$sponza" ]; then
      twice pocl-sponza "$sponza" --camera -10,3,0,10,5,0,0,1,0,60 --res 320x180 --spp 4 \
        --frames 30 --camera-path fixed --devices $d
    fi
    ;;
  *) echo "unknown set '$set' (pair31, pocl)" >&2; exit 2 ;;
  esac
done
