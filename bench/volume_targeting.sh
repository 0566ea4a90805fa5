#!/bin/sh
# Bruder et al. 2017's experiments on our volumes (docs/benchmarks.md, "Volumes";
# docs/volumes.md says what each baseline is and what still differs from the paper):
# frame-time targeting modes on a 300-frame sequence with two transfer-function switches,
# prediction-based balancing against the paper's static baseline, and the image quality
# of the adaptation spaces (the paper's three and our auto) against a fine reference
# (the paper's Table 4).
#   bench/volume_targeting.sh BUILD OUT [FRAMES] [PARTS]
#   PARTS: any of "targeting costmodel calibrate balance quality" (default: all)
# Needs ../shared/data/volumes. Three devices, as the paper: by default two CPU devices of
# one thread each, the second emulated at 0.4, and one OpenCL (PoCL) device; set
# POCL_MAX_PTHREAD_COUNT=1 and give the machine 3 cores, or set DEVICES to another list.
set -eu
build=${1:-build}
out=${2:-bench-out/volumes}
frames=${3:-300}
parts=${4:-"targeting costmodel calibrate balance quality"}
devices=${DEVICES:-cpu:threads=1,cpu:threads=1:speed=0.4,opencl}
data="$(dirname "$0")/../../shared/data/volumes"
seqs="$(dirname "$0")/sequences"
mr="$build/src/app/multiray"
mkdir -p "$out"
file_of() {
  case $1 in
    aneurism) echo "$data/aneurism_256x256x256_uint8.nhdr" ;;
    cranium) echo "$data/cranium_ct_256x256x108_int16le.nhdr" ;;
  esac
}
has() { case " $parts " in *" $1 "*) return 0 ;; esac; return 1; }
# Pure prediction with stealing (ours) is the balancer of the targeting lanes; bruder's
# zeta weighs the prediction as Eq. 3 prints it (zeta=1: no blend with uniform).
ours=bruder:zeta=1:steal=1
for vol in aneurism cranium; do
  file=$(file_of $vol)
  # Targeting: the paper's modes (two-pass probing a quarter of the last frame's quality)
  # and ours beside them (predict:q=0.9; two-pass:probe=fixed, a quarter of full quality).
  if has targeting; then
    "$mr" bench "$file" --res 256x192 --frames "$frames" --warmup 10 --ideal-frames 10 \
      --sequence "$seqs/$vol.json" --target-ms 100 --adapt-space ray \
      --adapt none,last-frame,two-pass,two-pass:probe=fixed,predict,predict:q=0.9 \
      --balancers $ours --devices "$devices" \
      --json "$out/$vol-targeting.json" --report "$out/$vol-targeting" > "$out/$vol-targeting.txt"
  fi
  # The cost model's settings: the paper's KRLS (gamma 0.00025, tolerance 0.006) and ours
  # (gamma 0.5, tolerance 0.001, 200 support vectors), each with and without the transfer
  # function's feature; compare RMSE, worst frame and "pred err" of the predict lanes.
  if has costmodel; then
    for cm in paper paper:tf=0 ours ours:tf=0; do
      "$mr" bench "$file" --res 256x192 --frames "$frames" --warmup 10 --ideal-frames 10 \
        --sequence "$seqs/$vol.json" --target-ms 100 --adapt predict --cost-model "$cm" \
        --adapt-space ray \
        --balancers $ours --devices "$devices" \
        --json "$out/$vol-costmodel-$cm.json" > "$out/$vol-costmodel-$cm.txt"
    done
  fi
  # Calibration of the paper's static baseline (§7.5): each device's cost per sample at
  # full quality over the whole sequence, averaged below over all sequences.
  if has calibrate; then
    "$mr" bench "$file" --res 256x192 --frames 100 --warmup 10 --ideal-frames 10 \
      --sequence "$seqs/$vol.json" --adapt none --balancers bruder --devices "$devices" \
      --json "$out/$vol-calibrate.json" > "$out/$vol-calibrate.txt"
  fi
done
# σ̄_i: the mean measured cost per sample of device i over every frame of every sequence.
sigma_bar() {
  python3 - "$out"/*-calibrate.json <<'PY'
import json, sys
sums, counts = [], []
for path in sys.argv[1:]:
    for run in json.load(open(path))["runs"]:
        for frame in run["frames"]:
            for i, s in enumerate(frame.get("measured_cost") or []):
                while len(sums) <= i: sums.append(0.0); counts.append(0)
                if s > 0: sums[i] += s; counts[i] += 1
print("/".join("%.6g" % (s / c) for s, c in zip(sums, counts)))
PY
}
# Balancing at full quality: the paper's static (σ̄ on the same k-d tiles) and ours (first
# frame's speeds on area bands), the paper's bruder (ζ = 0.5), pure prediction, ours.
if has balance; then
  sigma=$(sigma_bar)
  echo "static sigma (mean cost per sample over all sequences): $sigma" > "$out/static-sigma.txt"
  for vol in aneurism cranium; do
    "$mr" bench "$(file_of $vol)" --res 256x192 --frames 100 --warmup 10 --ideal-frames 10 \
      --sequence "$seqs/$vol.json" --adapt none \
      --balancers "bruder:sigma=$sigma,static,bruder,bruder:zeta=1,$ours,hybrid,queue" \
      --devices "$devices" --json "$out/$vol-balance.json" > "$out/$vol-balance.txt"
  done
fi
# Table 4: each adaptation space at the same target against every frame rendered at step
# 0.1 voxel (the paper's reference), aneurism, the first 60 frames, target 30 ms.
if has quality; then
  for space in image ray hybrid auto; do
    "$mr" bench "$(file_of aneurism)" --res 256x192 --frames 60 --warmup 10 --ideal-frames 1 \
      --sequence "$seqs/aneurism.json" --target-ms 30 --adapt none,predict --adapt-space $space \
      --reference-step 0.1 --balancers $ours --devices "$devices" \
      --json "$out/quality-$space.json" > "$out/quality-$space.txt"
  done
fi
