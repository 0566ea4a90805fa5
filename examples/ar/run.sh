#!/bin/sh
# Augmented reality from a capture (docs/ar.md): virtual objects composited over a
# sequence of real images, with their shadows on the real ground.
#
# The "capture" is made here, so that the result can be checked: the ground (ground.obj)
# is rendered along the poses of poses.json as the background frames a phone would film.
# Then the virtual objects (objects.obj) are rendered over them with a shadow catcher
# (--ground y=0) and, for comparison, the ground and the objects together as one scene.
# ar_NNNN.png and ref_NNNN.png should agree up to noise; ar_NNNN_rgba.png is the layer.
#
#   sh examples/ar/run.sh [OUT]        (OUT: ar-example/; MULTIRAY, RES, SPP, FRAMES override)
set -eu
here=$(dirname "$0")
out=${1:-ar-example}
multiray=${MULTIRAY:-multiray}
res=${RES:-320x240}
spp=${SPP:-32}
frames=${FRAMES:-8}
light="--env 0.3 --sun 40,35"
# Raw samples throughout (--denoise none): the composite cannot be denoised (--ground
# records no feature buffers), so the images it is compared with are not either.
common="--poses $here/poses.json --frames $frames --res $res --spp $spp $light -q --overwrite --denoise none"
mkdir -p "$out"
# The real images: the ground, as a camera would record it (display values as they are).
$multiray render "$here/ground.obj" $common --exposure 0 --tone clamp -o "$out/bg_####.png"
# The virtual objects over them.
$multiray render "$here/objects.obj" $common --ground y=0,albedo=0.5 \
  --background "$out/bg_####.png" -o "$out/ar_####.png"
# The reference: ground and objects rendered together (another seed, so its noise is its own).
$multiray render "$here/ground_and_objects.obj" $common --seed 1 --exposure 0 --tone clamp \
  -o "$out/ref_####.png"
echo "wrote $out/ar_*.png (composites), $out/ar_*_rgba.png (layers), $out/ref_*.png (references)"
