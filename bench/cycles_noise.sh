#!/bin/sh
# Equal noise against Blender Cycles (issue 35; docs/benchmarks.md, "Equal noise against
# Cycles"): who reaches a given noise sooner on the same work. The figure of merit is time
# x variance (for a Monte Carlo estimator with independent samples it does not depend on
# the sample count; lower is better), and samples per second beside it.
#   bench/cycles_noise.sh [BUILD] [OUT]
#   env: SPPS="16 64" RES=640x360 THREADS=1 REPEATS=2 SCENE=<Sponza OBJ>
#        MULTIRAY=<binary> (default BUILD/src/app/multiray; pass an older one to compare)
# Installs blender with apt-get when it is missing (the tests never run this script).
#
# The work (multiray's defaults for an OBJ without lights, rebuilt in Cycles by
# bench/cycles_sponza.py from multiray's own stats.json): Sponza, multiray's default camera,
# RES pixels, a constant white sky of 0.3 and a sun of irradiance 3 across 0.53 degrees,
# every material a Lambertian of Kd x the sRGB map_Kd texture, 8 bounces, no clamping,
# denoising or adaptive sampling, a box pixel filter one pixel wide, linear EXR.
# Differences that remain, named:
#   - sampling: multiray a shuffled Owen-scrambled Sobol sequence (render/shared/sobol.h),
#     Cycles 3.4 its default progressive multi-jitter; each renderer's own light choice,
#     sky sampling (multiray: cosine-weighted about the normal; Cycles: its background
#     light) and Russian roulette: these are what the comparison is about;
#   - Cycles' bilinear texture lookups against multiray's (the same texels, no MIP maps
#     on either), and Cycles' own ray offsets and float precision;
#   - time: multiray's frame_ms (the frame's render, scene already loaded); Cycles' wall
#     time of bpy.ops.render.render after a 1-sample warm-up render with persistent data
#     (so the BVH and the scene's sync are not counted; the film's conversion is).
# Each renderer renders every SPPS with seeds 1 and 2; the variance is that of one image
# from the pair (bench/noise_pair: mean of (A - B)^2 / 2 over pixels and channels), the
# same image means check the work is equal, and times are repeated REPEATS times.
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
out=${2:-$root/out/cycles-noise}
multiray=${MULTIRAY:-$build/src/app/multiray}
spps=${SPPS:-16 64}
res=${RES:-640x360}
threads=${THREADS:-1}
repeats=${REPEATS:-2}
scene=${SCENE:-$root/../shared/data/meshes/dabrovic_sponza/sponza.obj}
pair=$build/bench/noise_pair
if [ ! -x "$pair" ]; then
  echo "cycles_noise: build it first: cmake --build $build --target noise_pair" >&2
  exit 1
fi
if [ ! -f "$scene" ]; then
  echo "cycles_noise: no scene at $scene (set SCENE=)" >&2
  exit 1
fi
if ! command -v blender >/dev/null 2>&1; then
  echo "cycles_noise: installing blender (apt-get)" >&2
  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq blender >/dev/null
fi
mkdir -p "$out"
scene=$(cd "$(dirname "$scene")" && pwd)/$(basename "$scene")
w=${res%x*}
h=${res#*x}

# multiray's own settings for this scene (camera, sky, sun), for Cycles to copy.
"$multiray" render "$scene" --res "$res" --spp 1 --devices cpu:threads=1 -q --overwrite \
  --out "$out/probe.exr" 2>/dev/null
python3 - "$out" "$scene" "$w" "$h" "$threads" "$spps" <<'EOF'
import json, sys
out, scene, w, h, threads, spps = sys.argv[1:7]
st = json.load(open(out + "/probe.stats.json"))["settings"]
sun = st["sun"]
import math
solid = 2 * math.pi * (1 - math.cos(sun["half_angle_rad"]))
cfg = {"scene": scene, "width": int(w), "height": int(h), "threads": int(threads),
       "bounces": st["bounces"], "camera": st["camera"], "sky": st["environment"],
       "sun": {"direction": sun["direction"], "irradiance": sun["radiance"][0] * solid,
               "half_angle_rad": sun["half_angle_rad"]},
       "renders": [{"spp": int(n), "seed": s, "out": "%s/cycles_%s_seed%d.exr" % (out, n, s)}
                   for n in spps.split() for s in (1, 2)],
       "times": out + "/cycles_times.json"}
json.dump(cfg, open(out + "/cycles_settings.json", "w"), indent=1)
EOF

: >"$out/times.txt"
rep=1
while [ "$rep" -le "$repeats" ]; do
  for n in $spps; do
    for seed in 1 2; do
      "$multiray" render "$scene" --res "$res" --spp "$n" --seed "$seed" \
        --devices "cpu:threads=$threads" -q --overwrite --out "$out/multiray_${n}_seed$seed.exr" \
        2>/dev/null
      ms=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['frames'][0]['frame_ms'])" \
        "$out/multiray_${n}_seed$seed.stats.json")
      echo "multiray $n $seed $ms" >>"$out/times.txt"
    done
  done
  blender -b --factory-startup --python "$root/bench/cycles_sponza.py" -- \
    "$out/cycles_settings.json" >"$out/blender.log" 2>&1 ||
    { echo "cycles_noise: blender failed, see $out/blender.log" >&2; exit 1; }
  python3 -c "
import json, sys
for t in json.load(open(sys.argv[1])):
    print('cycles %d %d %.3f' % (t['spp'], t['seed'], 1000 * t['seconds']))" \
    "$out/cycles_times.json" >>"$out/times.txt"
  rep=$((rep + 1))
done

for r in multiray cycles; do
  for n in $spps; do
    echo "$r $n $("$pair" "$out/${r}_${n}_seed1.exr" "$out/${r}_${n}_seed2.exr")"
  done
done >"$out/noise.txt"

python3 - "$out" "$w" "$h" "$spps" "$threads" <<'EOF'
import json, sys
out, w, h, spps, threads = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4].split(), sys.argv[5]
times = {}
for line in open(out + "/times.txt"):
    r, n, _, ms = line.split()
    times.setdefault((r, n), []).append(float(ms))
noise = {}
for line in open(out + "/noise.txt"):
    r, n, doc = line.split(" ", 2)
    noise[(r, n)] = json.loads(doc)
def median(v):
    v = sorted(v); k = len(v)
    return v[k // 2] if k % 2 else 0.5 * (v[k // 2 - 1] + v[k // 2])
rows = []
print("| spp | renderer | ms (median [min, max], n) | Msamples/s | variance | time x variance | mean (R, G, B) |")
print("|---|---|---|---|---|---|---|")
for n in spps:
    fom = {}
    for r in ("multiray", "cycles"):
        t = times[(r, n)]; z = noise[(r, n)]
        ms = median(t)
        fom[r] = ms * z["variance"]
        rows.append({"renderer": r, "spp": int(n), "ms": t, "ms_median": ms,
                     "msamples_per_s": w * h * int(n) / ms / 1000, "variance": z["variance"],
                     "time_x_variance": fom[r], "mean": z["mean"]})
        print("| %s | %s | %.0f [%.0f, %.0f], %d | %.3f | %.3g | %.4g | %s |" % (
            n, r, ms, min(t), max(t), len(t), w * h * int(n) / ms / 1000, z["variance"],
            fom[r], ", ".join("%.5f" % m for m in z["mean"])))
    m, c = noise[("multiray", n)]["mean"], noise[("cycles", n)]["mean"]
    print("|  | multiray / cycles | %.2f | %.2f | %.2f | **%.2f** | mean %+.1f%% |" % (
        median(times[("multiray", n)]) / median(times[("cycles", n)]),
        median(times[("cycles", n)]) / median(times[("multiray", n)]),
        noise[("multiray", n)]["variance"] / noise[("cycles", n)]["variance"],
        fom["multiray"] / fom["cycles"], 100 * (sum(m) / sum(c) - 1)))
json.dump({"width": w, "height": h, "threads": int(threads), "rows": rows},
          open(out + "/summary.json", "w"), indent=1)
print("\n(columns of the ratio rows: time, samples/s of multiray over Cycles', variance, "
      "time x variance, and the image means' difference)")
EOF
