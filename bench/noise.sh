#!/bin/sh
# Noise of the built-in Cornell box against a high-spp reference, with and without --clamp
# (docs/noise.md): an image quality measurement, not a timing, so it runs on one thread at
# low priority and its times mean nothing.
#   bench/noise.sh [BUILD] [OUT]      (env: SPPS="16 64 256", CLAMPS="4", REF_SPP=4096)
# The reference uses another seed than the images (same seed: an image's samples would be
# the reference's own first ones). It is kept in OUT and reused when present.
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
out=${2:-$root/out/noise}
bin=$build/src/app/multiray
spps=${SPPS:-16 64 256}
clamps=${CLAMPS:-4}
ref_spp=${REF_SPP:-4096}
if [ ! -x "$build/bench/noise_compare" ]; then
  echo "noise: build it first: cmake --build $build --target noise_compare" >&2
  exit 1
fi
mkdir -p "$out"
render() {  # NAME ARGS...
  name=$1
  shift
  [ -f "$out/$name.exr" ] && return 0
  nice -n 10 "$bin" render --res 320x180 --threads 1 -q --overwrite \
    --out "$out/$name.exr" "$@"
}
render "ref$ref_spp" --spp "$ref_spp" --seed 1
render direct_emitters --spp 64 --bounces 0  # the light seen directly: left out of the * figures
images=""
for n in $spps; do
  render "spp$n" --spp "$n"
  images="$images $out/spp$n.exr"
  for x in $clamps; do
    render "spp${n}_clamp$x" --spp "$n" --clamp "$x"
    images="$images $out/spp${n}_clamp$x.exr"
  done
done
# shellcheck disable=SC2086
"$build/bench/noise_compare" "$out/ref$ref_spp.exr" "$out/direct_emitters.exr" $images
