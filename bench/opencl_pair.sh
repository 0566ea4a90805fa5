#!/bin/sh
# A real heterogeneous pair on a 2-core machine: the CPU device (Embree) on core 0 against
# PoCL's `basic` OpenCL driver on core 1 (its kernels run on the thread that enqueues them,
# which `cores=1` pins). Prints each device's standalone speed on the default scene and on
# Sponza, then runs `multiray bench` with every balancer on the pair (fixed camera, the
# same frames as the standalone runs).
#
# Usage: bench/opencl_pair.sh BUILD_DIR [OUT_DIR]   (results in docs/benchmarks.md)
#
# Standalone speed: `multiray render` with one device, 12 frames of a fixed camera; the
# speed is samples / device_ms (measured inside the device with steady_clock around every
# unit's enqueue + finish + read-back), median over frames 2..11 so the first frames'
# warm-up (page faults, PoCL's first launch) is left out.
set -eu
build=${1:?usage: bench/opencl_pair.sh BUILD_DIR [OUT_DIR]}
out=${2:-/tmp/multiray_opencl_pair}
bin="$build/src/app/multiray"
root=$(cd "$(dirname "$0")/.." && pwd)
sponza="$root/../shared/data/meshes/dabrovic_sponza/sponza.obj"
sponza_cam="-10,3,0,10,5,0,0,1,0,60"
common="--res 320x180 --spp 4"
mkdir -p "$out"
export POCL_DEVICES=basic

# Median Msamples/s of frames 2.. in a stats.json.
speed() {
  python3 -c '
import json, statistics, sys
frames = json.load(open(sys.argv[1]))["frames"][2:]
print("%.3f" % statistics.median(f["samples"][0] / f["device_ms"][0] / 1e3 for f in frames))
' "$1"
}

# Other tenants of the machine can take CPU time at any moment, and then two busy cores
# run slower than one. The probe counts a busy loop's iterations for 1 s on core 0 alone,
# then on cores 0 and 1 at once, and prints the pair's mean per-core rate / the solo rate
# (1.0: no contention; 0.5: both cores together get one core's worth).
probe() {
  python3 -c '
import multiprocessing as mp, os, time
def spin(core, q):
    os.sched_setaffinity(0, {core})
    n, end = 0, time.time() + 1.0
    while time.time() < end:
        n += 1
    q.put(n)
def run(cores):
    q = mp.Queue()
    ps = [mp.Process(target=spin, args=(c, q)) for c in cores]
    for p in ps: p.start()
    for p in ps: p.join()
    return [q.get() for _ in cores]
if __name__ == "__main__":
    solo = run([0])[0]
    pair = run([0, 1])
    print(f"contention probe: pair/solo = {sum(pair) / len(pair) / solo:.2f}")
'
}

# Runs one device alone on `scene` and prints its speed.
alone() {
  if [ "$1" = sponza ]; then args="$sponza --camera $sponza_cam"; else args=""; fi
  dir="$out/alone_$1_$(echo "$2" | tr ':=' '__')"
  # shellcheck disable=SC2086
  "$bin" render $args $common --frames 12 --camera-path fixed --devices "$2" --out "$dir" -q
  echo "standalone $1 $2: $(speed "$dir/stats.json") Msamples/s"
}

echo "load average before: $(cut -d' ' -f1-3 /proc/loadavg)"
probe
for scene in default sponza; do
  alone $scene cpu:threads=1:cores=0
  alone $scene opencl:0:cores=1
done
for scene in default sponza; do
  if [ "$scene" = sponza ]; then args="$sponza --camera $sponza_cam"; else args=""; fi
  # shellcheck disable=SC2086
  "$bin" bench $args $common --frames 30 --camera-path fixed \
    --devices cpu:threads=1:cores=0,opencl:0:cores=1 \
    --json "$out/bench_$scene.json"
done
probe
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
