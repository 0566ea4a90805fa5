#!/bin/sh
# Bruder et al. 2017 in a setting moved toward the paper's (issue 54, item 5): three
# devices, 1024x1024, 30-second sequences, the paper's cost model beside ours, Table 4's
# PSNRs against a 0.1-voxel reference and the fixed-step baselines (0.75 and 0.25 voxel).
# What still differs, and why: the devices are CPU threads and PoCL on two vCPUs (one of
# them at an emulated 0.4), ~300 ms a frame at full quality, so the paper's 25 ms target
# lies below what adaptation can reach here (at most 1/8 of the work); TARGET (default
# 100 ms) keeps the paper's ratio of about a third of the full-quality frame, and FRAMES
# (default 300) makes the sequence 30 s at that target. A timing: a quiet machine.
# REPEATS runs each lane that many times (files *-rN.json); bench/bruder_paper_summary.py
# prints each figure's median and range over them. VOLUME picks the aneurism (default) or
# the cranium (bench/sequences/cranium.json); SPACES the targeting's adaptation spaces,
# PARTS what runs (targeting, quality).
#   bench/bruder_paper_setting.sh BUILD OUT     (env: TARGET, FRAMES, QFRAMES, DEVICES,
#                                                REPEATS, VOLUME, SPACES, PARTS)
set -eu
build=${1:-build}
out=${2:-bench-out/bruder-paper}
target=${TARGET:-100}
frames=${FRAMES:-300}
qframes=${QFRAMES:-30}
devices=${DEVICES:-cpu:threads=1,cpu:threads=1:speed=0.4,opencl}
repeats=${REPEATS:-1}
spaces=${SPACES:-ray hybrid}
parts=${PARTS:-targeting quality}
root=$(cd "$(dirname "$0")/.." && pwd)
case ${VOLUME:-aneurism} in
aneurism) vol="$root/../shared/data/volumes/aneurism_256x256x256_uint8.nhdr" ;;
cranium) vol="$root/../shared/data/volumes/cranium_ct_256x256x108_int16le.nhdr" ;;
*) echo "bruder_paper_setting: VOLUME is aneurism or cranium, not '$VOLUME'" >&2; exit 2 ;;
esac
seq="$root/bench/sequences/${VOLUME:-aneurism}.json"
case $repeats in '' | *[!0-9]* | 0) echo "bruder_paper_setting: REPEATS must be a whole number >= 1" >&2; exit 2 ;; esac
mr="$build/src/app/multiray"
mkdir -p "$out"
[ -f "$vol" ] || { echo "skipping: $vol not found"; exit 0; }
common="--res 1024x1024 --sequence $seq --balancers bruder:zeta=1:steal=1 --devices $devices"
# Targeting: the reactive baseline and prediction, with each cost model (RMSE of the frame
# time against the target, worst frame).
# Ray space (the paper's first) and hybrid: at 1024x1024 here the step alone cannot bring
# a frame under the target (each pixel's ray costs without its samples).
has() { case " $parts " in *" $1 "*) return 0 ;; esac; return 1; }
r=1
while [ "$r" -le "$repeats" ]; do
  if has targeting; then
    for space in $spaces; do
      for cm in paper ours; do
        # shellcheck disable=SC2086 # $common is a list of words
        "$mr" bench "$vol" $common --frames "$frames" --warmup 10 --ideal-frames 5 --repeats 1 \
          --target-ms "$target" --adapt last-frame,predict --adapt-space $space --cost-model "$cm" \
          --json "$out/targeting-$space-$cm-r$r.json" > "$out/targeting-$space-$cm-r$r.txt"
      done
    done
  fi
  # Table 4: each adaptation space at the target, and the fixed steps without adaptation,
  # against every frame rendered at step 0.1 voxel.
  if has quality; then
    for space in image ray hybrid; do
      # shellcheck disable=SC2086
      "$mr" bench "$vol" $common --frames "$qframes" --warmup 2 --ideal-frames 1 --repeats 1 \
        --target-ms "$target" --adapt predict --adapt-space $space --cost-model paper \
        --reference-step 0.1 --json "$out/quality-$space-r$r.json" > "$out/quality-$space-r$r.txt"
    done
    for step in 0.75 0.25; do
      # shellcheck disable=SC2086
      "$mr" bench "$vol" $common --frames "$qframes" --warmup 2 --ideal-frames 1 --repeats 1 \
        --target-ms "$target" --adapt none --step "$step" --reference-step 0.1 \
        --json "$out/quality-step$step-r$r.json" > "$out/quality-step$step-r$r.txt"
    done
  fi
  r=$((r + 1))
done
/usr/bin/python3 "$root/bench/bruder_paper_summary.py" "$out" || true
