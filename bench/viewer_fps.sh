#!/bin/sh
# The live viewer's frame rate while dragging and its time to converge (issue 33), on the
# default scene at the viewer's defaults (640x360, --frame-spp 1, refined to 16 spp, the
# CPU's threads as one device): REPEATS runs of SECONDS of dragging each, one JSON line
# per run. A timing: run it on a quiet machine (docs/benchmarks.md).
#   bench/viewer_fps.sh [BUILD] [REPEATS] [SECONDS] [view options...]
set -eu
BUILD=${1:-build}
REPEATS=${2:-3}
SECONDS_=${3:-10}
[ $# -ge 3 ] && shift 3 || shift $#
cmake --build "$BUILD" --target viewer_fps > /dev/null
i=0
while [ "$i" -lt "$REPEATS" ]; do
  "$BUILD/bench/viewer_fps" "$SECONDS_" "$@"
  i=$((i + 1))
done
