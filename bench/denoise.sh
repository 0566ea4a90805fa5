#!/bin/sh
# Issue 52's quality goals (docs/noise.md, "The denoiser against raw samples"): raw images at
# 16, 64 and 256 spp and the denoised 16-spp image of three scenes against a 4096-spp
# reference of another seed — the built-in box, the README's Sponza hall and DamagedHelmet.
# An image quality measurement, not a timing: one thread, low priority, times mean nothing.
#   bench/denoise.sh [BUILD] [OUT]    (env: SCENES="box hall helmet", REF_SPP=4096,
#                                      METHODS="atrous")
# References are kept in OUT and reused. Needs ../shared/data for hall and helmet.
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
out=${2:-$root/out/denoise}
bin=$build/src/app/multiray
compare=$build/bench/denoise_compare
scenes=${SCENES:-box hall helmet}
ref_spp=${REF_SPP:-4096}
methods=${METHODS:-atrous}
data=$root/../shared/data/meshes
if [ ! -x "$compare" ]; then
  echo "denoise: build it first: cmake --build $build --target denoise_compare" >&2
  exit 1
fi
mkdir -p "$out"
for scene in $scenes; do
  case $scene in
  box) args="--res 320x180" ;;
  hall) args="$data/dabrovic_sponza/sponza.obj --res 240x136 --camera -10,3,0,10,5,0,0,1,0,60" ;;
  helmet) args="$data/damaged_helmet/DamagedHelmet.gltf --res 320x180" ;;
  *) echo "denoise: unknown scene '$scene' (box, hall, helmet)" >&2; exit 2 ;;
  esac
  case $scene in box) ;; *) [ -d "$data" ] || { echo "denoise: $scene skipped: no $data"; continue; } ;; esac
  render() {  # NAME ARGS...
    name=$1
    shift
    [ -f "$out/$name.exr" ] && return 0
    # shellcheck disable=SC2086 # $args is several words
    nice -n 10 "$bin" render $args --threads 1 -q --overwrite --exr -o "$out/$name.png" "$@"
  }
  render "${scene}_ref$ref_spp" --spp "$ref_spp" --seed 1 --denoise none
  images=""
  for spp in 16 64 256; do
    render "${scene}_spp$spp" --spp "$spp" --denoise none
    images="$images $out/${scene}_spp$spp.exr"
  done
  for m in $methods; do
    render "${scene}_spp16_$m" --spp 16 --denoise "$m"  # named: the EXR is denoised too
    images="$images $out/${scene}_spp16_$m.exr"
  done
  echo "== $scene"
  # shellcheck disable=SC2086
  "$compare" "$out/${scene}_ref$ref_spp.exr" $images
done
