#!/bin/sh
# Issue 50's regret table: the default (`auto`) against every subset of the devices on the
# real mixes here, at a size where the slow device does not pay (`small`: the default
# box, 320x180, 2 spp) and one where it does (`large`: 320x180, 16 spp), with --repeats
# blocks and intervals (`multiray bench --regret`, docs/benchmarks.md).
#
#   core-rusticl     one CPU thread + Mesa's rusticl (llvmpipe, one thread, wg=32)
#   2threads-rusticl two CPU threads + rusticl (three threads on two cores)
#   pocl-rusticl     PoCL (its pthread device) + rusticl
#   core-pocl        CPU thread on core 0 + PoCL's basic driver on core 1
#   core-slow002     CPU thread on core 0 + a CPU thread on core 1 at speed 0.02 (emulated)
#   pair31           CPU thread on core 0 + one on core 1 at speed 1/3 (emulated)
#
# Usage: bench/regret.sh BUILD_DIR [OUT_DIR] [SET[:SIZE] ...]   (default: every set at both
# sizes). Environment: REPEATS (3), FRAMES (24 small, 12 large). Run it on a quiet machine:
# each bench records its contention probe and says when its figures are not trustworthy.
# The rusticl sets need `mesa-opencl-icd` (scripts/install-deps.sh installs it).
set -eu
build=${1:?usage: bench/regret.sh BUILD_DIR [OUT_DIR] [SET[:SIZE] ...]}
out=${2:-/tmp/multiray_regret}
shift $(($# >= 2 ? 2 : 1))
all="core-rusticl 2threads-rusticl pocl-rusticl core-pocl core-slow002 pair31"
sets=${*:-}
if [ -z "$sets" ]; then
  for s in $all; do sets="$sets $s:small $s:large"; done
fi
bin="$build/src/app/multiray"
repeats=${REPEATS:-3}
mkdir -p "$out"
export RUSTICL_ENABLE=llvmpipe LP_NUM_THREADS=1

for item in $sets; do
  set=${item%%:*}
  size=${item#*:}
  [ "$size" = "$item" ] && size=small
  case $size in
  small) args="--res 320x180 --spp 2" frames=${FRAMES:-24} ;;
  large) args="--res 320x180 --spp 16" frames=${FRAMES:-12} ;;
  *) echo "unknown size '$size' (small, large)" >&2; exit 2 ;;
  esac
  case $set in
  core-rusticl) devices=cpu:threads=1,opencl:1:wg=32 ;;
  2threads-rusticl) devices=cpu:threads=2,opencl:1:wg=32 ;;
  pocl-rusticl) devices=opencl:0,opencl:1:wg=32 ;;
  core-pocl) devices=cpu:threads=1:cores=0,opencl:0:cores=1 ;;
  core-slow002) devices=cpu:threads=1:cores=0,cpu:threads=1:cores=1:speed=0.02 ;;
  pair31) devices=cpu:threads=1:cores=0,cpu:threads=1:cores=1:speed=0.3333 ;;
  *) echo "unknown set '$set'" >&2; exit 2 ;;
  esac
  case $set in core-pocl) export POCL_DEVICES=basic ;; *) unset POCL_DEVICES ;; esac
  name="$set-$size"
  echo "== $name ($(date -u +%H:%M:%S), load $(cut -d' ' -f1-3 /proc/loadavg))"
  # shellcheck disable=SC2086 # $args is several words
  "$bin" bench --regret $args --camera-path orbit --frames "$frames" \
    --warmup $((frames / 4)) --repeats "$repeats" --devices "$devices" \
    --json "$out/$name.json" > "$out/$name.txt" 2> "$out/$name.err" ||
    echo "exit $?: $(grep -h "error:" "$out/$name.err" | head -n 1)"
  # Exit 1 with a complete document when images differ between lanes: rusticl on
  # llvmpipe stops a work-item after 65,535 loop iterations (docs/devices.md), so its
  # pixels can differ from PoCL's although both are `opencl` devices.
  grep -A 12 "repeat blocks" "$out/$name.txt" | grep -v "^(" || true
  grep -h "not trustworthy" "$out/$name.err" || true
done
