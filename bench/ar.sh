#!/bin/sh
# Augmented reality's frames under every balancer (issue 33, docs/ar.md). With a shadow
# catcher the cost of a frame is concentrated: a pixel that sees the sky costs one ray, the
# ground a light sample and one bounce, the virtual objects whole paths. The same orbit of
# examples/ar is benched as an AR layer and, for contrast, as the whole scene (ground and
# objects path-traced everywhere), on two pinned CPU threads of equal speed and with the
# second at an emulated third of the speed.
#
# Usage: bench/ar.sh BUILD_DIR [OUT_DIR]
# Environment: BALANCERS (comma-separated specs), REPEATS (3), FRAMES (60).
# A timing: run it on a quiet machine; each bench records its own contention probe.
set -eu
build=${1:?usage: bench/ar.sh BUILD_DIR [OUT_DIR]}
out=${2:-/tmp/multiray_ar}
bin="$build/src/app/multiray"
ex=$(cd "$(dirname "$0")/../examples/ar" && pwd)
peers=cycles,equalizer,ospray-static,ospray-dynamic
balancers=${BALANCERS:-auto,hybrid,queue,static,semi-static,dlb,uniform,$peers}
repeats=${REPEATS:-3}
frames=${FRAMES:-60}
mkdir -p "$out"
light="--env 0.3 --sun 40,35"
# The example's first pose, orbiting the objects.
view="--camera -2.25,2.2,3.897,0.3,0.4,0,0,1,0,40 --camera-path orbit --res 640x360 --spp 1"
even=cpu:threads=1:cores=0,cpu:threads=1:cores=1
slow=cpu:threads=1:cores=0,cpu:threads=1:cores=1:speed=0.3333

one() {
  name=$1
  shift
  echo "== $name ($(date -u +%H:%M:%S), load $(cut -d' ' -f1-3 /proc/loadavg))"
  # shellcheck disable=SC2086 # $light and $view are several words each
  "$bin" bench "$@" $light $view --frames "$frames" --repeats "$repeats" \
    --balancers "$balancers" --json "$out/$name.json" > "$out/$name.txt"
  grep -A 20 "^3 repeat blocks\|^[0-9]* repeat blocks" "$out/$name.txt" | head -n 18
}

one ar-even "$ex/objects.obj" --ground y=0 --devices $even
one ar-pair31 "$ex/objects.obj" --ground y=0 --devices $slow
one full-pair31 "$ex/ground_and_objects.obj" --devices $slow
