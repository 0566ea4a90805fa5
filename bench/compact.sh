#!/bin/sh
# The compact scene against full precision (issue 11; the table of docs/benchmarks.md,
# "Compact scene"): sizes by part, render time on one CPU thread, the same OpenCL kernel
# on the flat and the compact tree (when an OpenCL device is found) and PSNR, for the
# shared meshes and one generated large mesh (the flight helmet split to 6.06 M triangles).
#   bench/compact.sh [BUILD]      (default build/; needs ../shared/data)
# JSON lines go to bench-out/compact.jsonl, the table to the terminal.
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
data=$root/../shared/data/meshes
bin=$build/bench/compact_bench
[ -x "$bin" ] || { echo "compact.sh: build $bin first (cmake --build $build --target compact_bench)"; exit 1; }
[ -d "$data" ] || { echo "compact.sh: skipped: $data not found"; exit 0; }
mkdir -p "$root/bench-out"
out=$root/bench-out/compact.jsonl
: > "$out"
"$bin" --res 320x180 --spp 2 --bounces 4 --reps 3 --opencl \
  "$data/stanford_bunny/bunny.ply" \
  "$data/dabrovic_sponza/sponza.obj" \
  "$data/damaged_helmet/DamagedHelmet.gltf" \
  "$data/flight_helmet/FlightHelmet.gltf" >> "$out"
"$bin" --res 320x180 --spp 1 --bounces 4 --reps 1 --subdivide 3 --opencl \
  "$data/flight_helmet/FlightHelmet.gltf" >> "$out"
echo "compact.sh: wrote $out"
