#!/bin/sh
# Balancers at scale (issue "Balancers at scale and against their peers"): traces recorded
# on this machine, replayed by `multiray simulate` on 2..1024 virtual devices behind the
# emulated LAN and mobile Wi-Fi links, with every balancer (ours and the peers'), in virtual
# time. Also: the simulator checked against real runs, and Seo et al.'s Table 9 setting.
#
# Usage: bench/scaling.sh BUILD_DIR [OUT_DIR]   (results in docs/benchmarks.md)
#
# Traces: one CPU core (cpu:threads=1) renders 640x360, 4 spp, a 40-frame orbit with the
# tile queue (16-px tiles), so every tile's cost is measured (steady_clock inside the
# device). The default scene (Cornell box) has nearly even cost per pixel; Sponza's is
# skewed (open sky cheap, colonnades dear). Virtual devices are `--slowdown 20` times
# slower than the recording core (a frame takes seconds on one of them, as on Seo's phones),
# speeds random in [0.3, 1], 5% per-frame noise. Efficiency = (frame cost / sum of speeds)
# / simulated frame time at the master, frames 10..99.
set -eu
build=${1:?usage: bench/scaling.sh BUILD_DIR [OUT_DIR]}
out=${2:-/tmp/multiray_scaling}
bin="$build/src/app/multiray"
root=$(cd "$(dirname "$0")/.." && pwd)
sponza="$root/../shared/data/meshes/dabrovic_sponza/sponza.obj"
mkdir -p "$out"
anim="--frames 40 --camera-path orbit:40 -q"
record="--res 640x360 --spp 4 $anim"

"$bin" render $record --devices cpu:threads=1 --balancer queue:tile=16 \
  --trace "$out/cornell.trace" --out "$out/cornell_frames"
scenes="cornell"
if [ -f "$sponza" ]; then
  "$bin" render "$sponza" $record --devices cpu:threads=1 --balancer queue:tile=16 \
    --trace "$out/sponza.trace" --out "$out/sponza_frames"
  scenes="cornell sponza"
fi

counts="2,4,8,16,32,64,128,256,512,1024"
for scene in $scenes; do
  for link in lan wifi; do
    "$bin" simulate "$out/$scene.trace" --devices $counts --speeds random:0.3 --noise 0.05 \
      --slowdown 20 --link $link --frames 100 --warmup 10 \
      --json "$out/${scene}_$link.json" --plot "$out/${scene}_$link.svg" \
      > "$out/${scene}_$link.txt"
  done
done

# Seo et al. Table 9: equal workers on the mobile link, 1..16 workers; static batched
# (round-robin tiles, sent once per frame: ospray-static) vs dynamic (tile queue, a round
# trip per tile: queue), 64-px tiles, and ours.
"$bin" simulate "$out/cornell.trace" --devices 1,2,4,8,16 --speeds equal --slowdown 20 \
  --link wifi --frames 100 --warmup 10 \
  --balancers ospray-static:tile=64,queue:tile=64,ospray-dynamic:tile=64,hybrid,semi-static,dlb \
  --json "$out/seo_table9.json" > "$out/seo_table9.txt"

# The simulator against real runs: a trace of the tile queue on a real pair (core + an
# emulated half-speed core) predicts what hybrid and semi-static do on the same pair.
pair="--res 320x180 --spp 4 --frames 30 --camera-path orbit:30 -q --devices cpu:threads=1,cpu:threads=1:speed=0.5"
"$bin" render $pair --balancer queue:tile=16 --trace "$out/pair_queue.trace" --out "$out/pair_q"
for b in hybrid semi-static uniform; do
  "$bin" render $pair --balancer $b --out "$out/pair_$b"
  "$bin" simulate "$out/pair_queue.trace" --devices 2 --speeds list:1/0.5 --balancers $b \
    --warmup 0 --json "$out/pair_sim_$b.json" > /dev/null
done
python3 - "$out" <<'PY'
import json, sys
out = sys.argv[1]
print("simulator vs real (frames 3..29): balancer, mean real ms, mean simulated ms, mean |error|")
for b in ["hybrid", "semi-static", "uniform"]:
    real = [max(f["device_ms"]) for f in json.load(open(f"{out}/pair_{b}/stats.json"))["frames"]]
    sim = json.load(open(f"{out}/pair_sim_{b}.json"))["runs"][0]["frame_ms"]
    pairs = list(zip(real, sim))[3:]
    err = sum(abs(s - r) / r for r, s in pairs) / len(pairs)
    print(f"{b:12s} {sum(r for r, _ in pairs)/len(pairs):8.2f} {sum(s for _, s in pairs)/len(pairs):8.2f} {100*err:6.1f}%")
PY

# Leria et al.: a 3x3 light field (320x180 per view, 1 spp) on a heterogeneous pair and
# quadruple; speed-up of each balancer over uniform = uniform's frame time / its own.
"$bin" render $anim --res 320x180 --spp 1 --views 3x3 --devices cpu:threads=1 \
  --balancer queue:tile=16 --trace "$out/lightfield.trace" --out "$out/lightfield_frames"
leria="--frames 100 --warmup 10 --balancers uniform,dlb,hybrid,semi-static,cycles,equalizer"
"$bin" simulate "$out/lightfield.trace" --devices 2 --speeds list:1/0.33 $leria \
  > "$out/leria_2.txt"
"$bin" simulate "$out/lightfield.trace" --devices 4 --speeds list:1/0.8/0.5/0.25 $leria \
  > "$out/leria_4.txt"

# Harada (GPU Pro 7 ch. 4, edge sampling after Mitchell 1987): adaptive AO (edge pixels 5
# spp, others 1); deviation of device times on two devices (1 : 0.5) and four whose speeds
# sum to 2 (0.8, 0.6, 0.4, 0.2).
"$bin" render $anim --res 640x360 --integrator ao --sampling adaptive --devices cpu:threads=1 \
  --balancer queue:tile=16 --trace "$out/adaptive_ao.trace" --out "$out/adaptive_frames"
"$bin" simulate "$out/adaptive_ao.trace" --devices 2 --speeds list:1/0.5 --noise 0.05 \
  --frames 100 --warmup 10 --balancers semi-static,hybrid,queue,cycles,equalizer > "$out/harada_2.txt"
"$bin" simulate "$out/adaptive_ao.trace" --devices 4 --speeds list:0.8/0.6/0.4/0.2 --noise 0.05 \
  --frames 100 --warmup 10 --balancers semi-static,hybrid,queue,cycles,equalizer > "$out/harada_4.txt"
echo "results in $out"
