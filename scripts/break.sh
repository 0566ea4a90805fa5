#!/bin/sh
# Deliberate breaks: each tests/breaks/NAME.patch breaks the code in one small way; this
# applies it, rebuilds what it names, runs the tests that should catch it, and takes it
# back. A break is "caught" when those tests fail; a break no test catches is a missing
# test (docs/testing.md has the table).
#
#   scripts/break.sh list          every break, with what it does and its tests
#   scripts/break.sh NAME ...      these breaks (NAME without .patch)
#   scripts/break.sh all           every break; exit 1 if any is not caught
#
# A patch file starts with three header lines, then a git diff:
#   What: one line on what the break does
#   Tests: a ctest -R regular expression
#   Targets: the CMake targets to rebuild (space-separated)
# BUILD (default build/) is the Release build to use; the tree must have no uncommitted
# change in the files a patch touches. Interrupted, it takes the break back.
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD:-$root/build}
dir="$root/tests/breaks"
field() { sed -n "s/^$2: //p" "$1" | head -n 1; }

[ $# -ge 1 ] || { sed -n '2,17p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
if [ "$1" = list ]; then
  for p in "$dir"/*.patch; do
    printf '%-28s %s\n%-28s tests: %s\n' "$(basename "$p" .patch)" "$(field "$p" What)" "" \
      "$(field "$p" Tests)"
  done
  exit 0
fi
[ -f "$build/CMakeCache.txt" ] || { echo "break: no build in $build (run make build first)" >&2; exit 2; }
names="$*"
[ "$1" = all ] && names=$(for p in "$dir"/*.patch; do basename "$p" .patch; done)

applied=""
restore() { [ -z "$applied" ] || git -C "$root" apply -R "$applied"; applied=""; }
trap 'restore' EXIT
trap 'restore; exit 130' INT TERM

missed=0
for name in $names; do
  patch="$dir/$name.patch"
  [ -f "$patch" ] || { echo "break: no $patch" >&2; exit 2; }
  tests=$(field "$patch" Tests)
  targets=$(field "$patch" Targets)
  if ! git -C "$root" apply --check "$patch" 2> /dev/null; then
    echo "$name: STALE (the patch no longer applies; rewrite it)"
    missed=1
    continue
  fi
  git -C "$root" apply "$patch"
  applied="$patch"
  log="$build/break-$name.log"
  if ! cmake --build "$build" -j"${JOBS:-2}" --target $targets > "$log" 2>&1; then
    restore
    echo "$name: DOES NOT BUILD (a break must compile; $log)"
    missed=1
    continue
  fi
  if (cd "$build" && ctest -R "$tests" -j"${JOBS:-2}" --timeout 300 >> "$log" 2>&1); then
    echo "$name: MISSED (no test in '$tests' failed; $log)"
    missed=1
  else
    failed=$(sed -n 's/^[[:space:]]*[0-9]* - \([^ ]*\) .*/\1/p' "$log" | tr '\n' ' ')
    echo "$name: caught by $failed"
  fi
  restore
done
# Rebuild what the breaks touched, so the build is the tree's again.
cmake --build "$build" -j"${JOBS:-2}" > /dev/null 2>&1 || echo "break: the rebuild after the breaks failed"
exit $missed
