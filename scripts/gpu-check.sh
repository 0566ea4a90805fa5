#!/bin/sh
# What to run on a machine with a real GPU OpenCL driver (NVIDIA, AMD, Intel), which the
# project cannot test itself. Lists the OpenCL implementations and devices with their
# driver versions, runs the OpenCL tests on each implementation (each alone in its process
# through OCL_ICD_VENDORS, as tests/opencl/CMakeLists.txt does for rusticl), benches the
# CPU with the GPU, and writes one markdown report to send back.
#
#   scripts/gpu-check.sh [REPORT]   default REPORT: gpu-check-HOST-DATE.md here
#
# Without a GPU (this project's own machines) the first device of each implementation
# (PoCL, Mesa's rusticl on llvmpipe) stands in for one, and the report says so.
# Environment (defaults keep a run to a few minutes):
#   BUILD=build/        the Release build (make build)
#   TESTS=quick|all|none  quick: the fast image tests (split, wg, Sobol, same-seed match,
#                       volume, batch, failure) and the implementations' images; all:
#                       every OpenCL test (slow on CPU stand-ins)
#   RES=320x180 FRAMES=12 REPEATS=3  the bench: frames, each balancer timed REPEATS times
#   BALANCERS=queue,semi-static      the bench's balancers
#   OCLGRIND=0          1: also the Oclgrind check of every kernel (minutes)
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD:-$root/build}
bin="$build/src/app/multiray"
tests="$build/tests/opencl/opencl_tests"
[ -x "$bin" ] || { echo "gpu-check: no $bin (run make build first)" >&2; exit 2; }
[ -x "$tests" ] || { echo "gpu-check: no $tests (run make build first)" >&2; exit 2; }
TESTS=${TESTS:-quick}
case "$TESTS" in quick | all | none) ;; *) echo "gpu-check: TESTS must be quick, all or none" >&2; exit 2 ;; esac
report=${1:-gpu-check-$(hostname)-$(date +%Y%m%d-%H%M%S).md}
: > "$report" || { echo "gpu-check: cannot write $report" >&2; exit 2; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# rusticl lists only the drivers RUSTICL_ENABLE names (llvmpipe here; radeonsi, iris on GPUs).
export RUSTICL_ENABLE="${RUSTICL_ENABLE:-radeonsi,iris,nouveau,llvmpipe}"
export LP_NUM_THREADS="${LP_NUM_THREADS:-1}"
vendors=${OCL_ICD_VENDORS:-/etc/OpenCL/vendors}
out() { printf '%s\n' "$*" >> "$report"; }
say() { printf 'gpu-check: %s\n' "$*" >&2; }

commit=$(git -C "$root" rev-parse --short HEAD 2> /dev/null || echo unknown)
git -C "$root" diff --quiet HEAD 2> /dev/null || commit="$commit (with uncommitted changes)"
out "# multiray GPU check"
out ""
out "- date: $(date -u +%Y-%m-%dT%H:%M:%SZ)"
out "- commit: $commit"
out "- host: $(hostname), $(uname -sr), $(grep -m1 'model name' /proc/cpuinfo | sed 's/.*: //'), $(nproc) CPUs"
out "- settings: TESTS=$TESTS RES=${RES:-320x180} FRAMES=${FRAMES:-12} REPEATS=${REPEATS:-3} RUSTICL_ENABLE=$RUSTICL_ENABLE"

# Implementations: every ICD file through which multiray sees a device.
out ""
out "## OpenCL implementations and devices"
out ""
impls=""
gpus=""
for icd in "$vendors"/*.icd; do
  [ -f "$icd" ] || continue
  OCL_ICD_VENDORS="$icd" "$bin" devices > "$tmp/devices" 2>&1 || true
  grep -q '^opencl ' "$tmp/devices" || { out "- $(basename "$icd"): no device"; continue; }
  impls="$impls $icd"
  out "- $(basename "$icd"):"
  grep '^opencl \|^  opencl:[0-9]' "$tmp/devices" | sed 's/^/    /' >> "$report"
  # A GPU: "(gpu)" in the name column; remembered as ICD|index.
  grep '^opencl .*(gpu)' "$tmp/devices" | sed 's/.*opencl:\([0-9]*\).*/\1/' | while read -r i; do
    echo "$icd|$i"
  done > "$tmp/gpus"
  gpus="$gpus $(cat "$tmp/gpus")"
done
[ -n "$impls" ] || { out ""; out "No OpenCL device found: nothing to check."; say "no OpenCL device; report in $report"; exit 1; }
gpus=$(echo $gpus)
out ""
if [ -n "$gpus" ]; then
  out "GPUs found: $gpus (ICD|index)."
else
  out "**No GPU found**: the first device of each implementation above stands in for one"
  out "(CPU implementations: the figures below say nothing about GPU speed)."
  for icd in $impls; do gpus="$gpus $icd|0"; done
  gpus=$(echo $gpus)
fi

# Tests: the OpenCL test program on each implementation, opencl:0 its first device.
filter="-OpenClImplementations.*:OpenClOclgrind.*"
[ "$TESTS" = quick ] && filter="OpenClSplit.*:OpenClSobol.*:OpenClWorkGroup.*:OpenClLitPlane.*:OpenClMatch.SameSeed*:OpenClVolume.*:OpenClBatch.VolumeImages*:OpenClBatch.Reports*:OpenClEngine.InjectedFailure*:OpenClStrict.*"
out ""
out "## OpenCL tests"
out ""
status=0
if [ "$TESTS" != none ]; then
  for icd in $impls; do
    say "tests on $(basename "$icd")"
    start=$(date +%s)
    if OCL_ICD_VENDORS="$icd" timeout 1800 "$tests" --gtest_brief=1 --gtest_filter="$filter" > "$tmp/tests" 2>&1; then
      result=passed
    else
      result=FAILED
      status=1
    fi
    passed=$(sed -n 's/^\[  PASSED  \] \([0-9]*\) test.*/\1/p' "$tmp/tests")
    skipped=$(sed -n 's/^\[  SKIPPED \] \([0-9]*\) test.*/\1/p' "$tmp/tests")
    out "- $(basename "$icd"): $result in $(($(date +%s) - start)) s (${passed:-0} passed, ${skipped:-0} skipped; filter $filter)"
    if [ $result = FAILED ]; then
      out '```'
      grep -A12 '^\[  FAILED  \]\|Failure' "$tmp/tests" | head -60 >> "$report"
      out '```'
    fi
  done
  say "the same images on every implementation"
  if timeout 1800 "$tests" --gtest_brief=1 --gtest_filter='OpenClImplementations.*' > "$tmp/impl" 2>&1; then
    out "- every kernel's images across implementations: $(grep -q SKIPPED "$tmp/impl" && echo "skipped (one implementation)" || echo "bit-identical")"
  else
    status=1
    out "- every kernel's images across implementations: **DIFFER**"
    out '```'
    grep -B2 -A6 'Failure' "$tmp/impl" | head -60 >> "$report"
    out '```'
  fi
  if [ "${OCLGRIND:-0}" = 1 ]; then
    say "Oclgrind (slow)"
    "$tests" --gtest_brief=1 --gtest_filter='OpenClOclgrind.*' > "$tmp/grind" 2>&1 && r=clean || { r=REPORTS; status=1; }
    out "- Oclgrind, every kernel: $r"
  fi
fi

# Bench: the CPU with each GPU (or stand-in), every balancer REPEATS times.
out ""
out "## Bench: CPU + GPU"
for g in $gpus; do
  icd=${g%|*}
  index=${g#*|}
  say "bench cpu + opencl:$index of $(basename "$icd")"
  out ""
  out "### cpu:threads=0 + opencl:$index ($(basename "$icd"))"
  out ""
  out '```'
  if OCL_ICD_VENDORS="$icd" timeout 1800 "$bin" bench --devices "cpu:threads=0,opencl:$index" \
    --res "${RES:-320x180}" --frames "${FRAMES:-12}" --repeats "${REPEATS:-3}" \
    --balancers "${BALANCERS:-queue,semi-static}" --ideal-frames 4 \
    --json "$tmp/bench.json" > "$tmp/bench" 2>&1; then
    cat "$tmp/bench" >> "$report"
  else
    status=1
    tail -20 "$tmp/bench" >> "$report"
    out "(the bench failed)"
  fi
  out '```'
done
say "report in $report"
exit $status
