#!/bin/bash
# Builds the libFuzzer targets (clang-15, the `fuzz` CMake preset in build-fuzz/, or the
# -O0 `fuzz-smoke` preset in build-fuzz-smoke/ for smoke runs) and runs each one.
# fuzz/README.md describes the targets.
#
#   fuzz/run.sh smoke  each target for FUZZ_SMOKE_SECONDS (default 3) from its seed corpus,
#                      with a fixed seed; new inputs are not kept (`make fuzz-smoke`)
#   fuzz/run.sh long   each target for FUZZ_SECONDS (default 60), growing its corpus in
#                      build-fuzz/corpus/<target>/ (`make fuzz`)
#
# FUZZ_TARGETS="ply obj" picks targets; JOBS sets the build's parallelism;
# FUZZ_KNOWN=1 sets MULTIRAY_FUZZ_KNOWN=1, which a target may read to keep inputs of a
# known, still open finding (docs/reliability.md); fuzz_assimp skips Quick3D (F6).
# Crashes, leaks, timeouts and out-of-memory inputs are kept in FUZZ_CRASH_DIR/<target>/ (default
# fuzz/crashes/, not committed); the exit status is 1 when a target found one. Without
# clang++-15 and its libFuzzer runtime (scripts/install-deps.sh installs them) it says so
# and exits 0.
set -eu
mode=${1:-smoke}
root=$(cd "$(dirname "$0")/.." && pwd)
# Smoke runs use their own -O0 build (the `fuzz-smoke` preset, build-fuzz-smoke/): it
# builds in about 60% of the time of the -O1 one.
preset=fuzz
[ "$mode" = smoke ] && preset=fuzz-smoke
build="$root/build-$preset"
targets=${FUZZ_TARGETS:-"ply obj gltf glb camera_json camera_render trace cli volume transfer messages viewer sequence assimp"}
crashes=${FUZZ_CRASH_DIR:-"$root/fuzz/crashes"}
case "$mode" in
  smoke) seconds=${FUZZ_SMOKE_SECONDS:-3} ;;
  long) seconds=${FUZZ_SECONDS:-60} ;;
  *) echo "usage: fuzz/run.sh smoke|long" >&2; exit 2 ;;
esac

if ! command -v clang++-15 > /dev/null 2>&1; then
  echo "fuzz: skipped (clang++-15 not found; scripts/install-deps.sh installs clang-15)"
  exit 0
fi
runtime="$(clang++-15 -print-resource-dir)/lib/linux/libclang_rt.fuzzer-x86_64.a"
if [ ! -f "$runtime" ]; then
  echo "fuzz: skipped (no libFuzzer runtime $runtime; install libclang-common-15-dev)"
  exit 0
fi

start=$(date +%s)
mkdir -p "$build"
if [ ! -f "$build/CMakeCache.txt" ]; then
  (cd "$root" && cmake --preset "$preset") > "$build/configure.log" 2>&1 ||
    { cat "$build/configure.log"; exit 1; }
fi
if ! cmake --build "$build" --target multiray_fuzzers -j"${JOBS:-$(nproc)}" \
  > "$build/build.log" 2>&1; then
  grep -E "error|Error" "$build/build.log" | head -n 40
  echo "fuzz: the fuzz targets do not build (log: $build/build.log)"
  exit 1
fi
built=$(date +%s)

seeds="$build/seeds"
rm -rf "$seeds"
"$root/fuzz/seed-corpus.sh" "$seeds" > /dev/null

# The sanitizers' settings: LeakSanitizer knows oneTBB's one benign leak (cmake/lsan.supp).
symbolizer=$(command -v llvm-symbolizer-15 || command -v llvm-symbolizer || true)
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1${symbolizer:+:external_symbolizer_path=$symbolizer}}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
if [ -n "${FUZZ_KNOWN:-}" ]; then export MULTIRAY_FUZZ_KNOWN=1; fi
# The targets' scratch folders (fuzz_support.h), removed however the targets end.
shm=/dev/shm
[ -d $shm ] && [ -w $shm ] || shm=${TMPDIR:-/tmp}
MULTIRAY_FUZZ_SCRATCH=$(mktemp -d "$shm/multiray-fuzz.XXXXXX")
export MULTIRAY_FUZZ_SCRATCH
trap 'rm -rf "$MULTIRAY_FUZZ_SCRATCH"' EXIT
export LSAN_OPTIONS="${LSAN_OPTIONS:-suppressions=$root/cmake/lsan.supp}"

# One target: its run, then one line (and the finding's lines) in $build/logs/$1.result;
# the file $build/logs/$1.failed marks a finding.
run_target() {
  t=$1
  bin="$build/fuzz/fuzz_$t"
  mkdir -p "$crashes/$t" "$build/logs"
  log="$build/logs/$t-$mode.log"
  result="$build/logs/$t.result"
  rm -f "$build/logs/$t.failed"
  if [ "$t" = viewer ] && [ ! -x "$bin" ]; then  # built only with civetweb (the viewer)
    echo "fuzz_viewer: skipped (no viewer in this build: libcivetweb-dev not found)" > "$result"
    return 0
  fi
  if [ "$mode" = smoke ]; then
    work="$build/smoke-corpus/$t"
    rm -rf "$work"
    extra="-seed=1"
  else
    work="$build/corpus/$t"
    extra=""
  fi
  mkdir -p "$work"
  dict=""
  case $t in
    glb) dict="-dict=$root/fuzz/dict/gltf.dict" ;;
    camera_render) extra="$extra -max_len=64" ;;
    cli) extra="$extra -max_len=1024"; dict="-dict=$root/fuzz/dict/cli.dict" ;;
    *) [ -f "$root/fuzz/dict/$t.dict" ] && dict="-dict=$root/fuzz/dict/$t.dict" ;;
  esac
  # -close_fd_mask=3: the targets' own output (warnings, the CLI's lines) is dropped;
  # libFuzzer's, the sanitizers' and fuzz::fail()'s reports still reach the log.
  # shellcheck disable=SC2086  # $extra and $dict are lists of flags
  if "$bin" -max_total_time="$seconds" -timeout=30 -rss_limit_mb=2048 -print_final_stats=1 \
    -close_fd_mask=3 \
    -artifact_prefix="$crashes/$t/" $extra $dict "$work" "$seeds/$t" > "$log" 2>&1; then
    status=ok
  else
    status=FAILED
    touch "$build/logs/$t.failed"
  fi
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -n 1 | cut -d' ' -f2)
  echo "fuzz_$t: ${runs:-?} runs in ${seconds} s, coverage ${cov:-?} edges, $status" > "$result"
  if [ $status = FAILED ]; then
    grep -E "^(==[0-9]+==ERROR|SUMMARY|multiray fuzz:)|runtime error|Test unit written|^ +#[0-9] " \
      "$log" | head -n 30 >> "$result"
    echo "  log: $log" >> "$result"
    echo "  reproduce: $bin $crashes/$t/<crash file>" >> "$result"
  fi
}

# JOBS targets at a time (each libFuzzer run is one process on one core): a new one starts
# as soon as any ends (bash's wait -n), not when the slower of a pair does. Reported in
# the order of $targets.
lanes=${JOBS:-$(nproc)}
running=0
for t in $targets; do
  run_target "$t" &
  running=$((running + 1))
  if [ "$running" -ge "$lanes" ]; then
    wait -n || true
    running=$((running - 1))
  fi
done
wait
failed=""
for t in $targets; do
  cat "$build/logs/$t.result"
  if [ -f "$build/logs/$t.failed" ]; then failed="$failed $t"; fi
done
end=$(date +%s)
echo "fuzz: $mode run of $(echo " $targets" | wc -w | tr -d ' ') targets:" \
  "build $((built - start)) s, fuzzing $((end - built)) s"
if [ -n "$failed" ]; then
  echo "fuzz: findings in:$failed (inputs in $crashes/)"
  exit 1
fi
