#!/bin/sh
# Issue 35: multiray's CPU volume raycaster against VTK 9.1's CPU raycaster
# (vtkFixedPointVolumeRayCastMapper, bench/vtk_volume.py) per core, on equal work:
#   bench/volume_vs_vtk.sh BUILD_DIR [OUT_DIR]
#   env: FRAMES (timed frames per run, 20), WARMUP (2), REPEATS (3), THREADS ("1 2")
# Both run on the same machine, interleaved REPEATS times; VTK is Debian's python3-vtk9 under
# xvfb-run -a, installed here with apt-get when missing (never by the tests).
#
# The same work on both sides:
#   aneurism 256^3 uint8, 256x192 pixels, one ray per pixel through the pixel centre, the
#   fixed camera below (multiray's default volume view, given explicitly to both), rays of
#   0.5 voxel lengths, opacity per 1 voxel length corrected for the step, trilinear
#   samples, the `angio` transfer function (its fractions of [min, max] as data values for
#   VTK), headlight shading 0.3 ambient + 0.7 two-sided diffuse, no specular, black
#   background, 1 and 2 threads. (VTK scales the ambient term by the light's ambient
#   colour, black by default: bench/vtk_volume.py adds a headlight with a white one.)
# Every difference in the work that remains:
# - Gradients: multiray takes central differences of trilinear samples at every shaded
#   sample (6 extra fetches); VTK precomputes one gradient per voxel once (the first render,
#   a warm-up frame here), quantizes its direction to a 2-byte table entry and shades the 8
#   corners, interpolating the result. VTK's per-frame work is cheaper; its shading coarser.
#   Where the gradient is zero VTK shades with the ambient term alone; multiray leaves the
#   transfer function's colour unshaded.
# - Light direction: VTK shades every sample with the camera's central view direction (one
#   table per frame); multiray with each ray's own direction (|cos(gradient, ray)|).
# - Arithmetic: VTK looks up and composites colours and opacities in 15-bit fixed point;
#   multiray in float.
# - Transfer-function tables: multiray bakes a table over [min, max] and interpolates it;
#   VTK builds its own fixed-point tables over the data's range.
# - Step placement: multiray's samples lie on a lattice from the grid's entry point;
#   VTK's from its own ray set-up. Same spacing. (Pixel positions agree: the two
#   footprints match best unshifted.)
# - Grid box: multiray's box reaches half a voxel past the outer voxel centres (samples
#   clamp there); VTK's bounds end at the outer centres.
# - Early ray termination: multiray at accumulated opacity 0.99; VTK when the remaining
#   transparency falls below 0xff/0x7fff (opacity above ~0.992).
# - Empty space: multiray skips blocks whose opacity is zero (exact: it never changes the
#   image); VTK leaps over space with its own min-max volume of small blocks.
# - Output: multiray's PNG is its float radiance encoded sRGB. VTK's result is its mapper's
#   15-bit image, which it then draws into the window as a texture; that drawing blurs it by
#   about a pixel (a 1-pixel halo round every vessel), so the image comparison reads the
#   mapper's own image (bench/vtk_volume.py's `image`; the window is kept as `_display`),
#   rounded to 8 bits and encoded sRGB as multiray encodes (dark values then carry VTK's
#   8-bit quantization, coarse in sRGB).
# - Prediction: multiray runs with --prepass-stride 0, without its cost model's pre-pass
#   rays and learning (work for balancing several devices that VTK has no counterpart of;
#   one device is not balanced, and the image is the same bit for bit).
# - Timing: multiray's frame_ms (stats.json: planning, rendering, gathering one frame);
#   VTK's wall time of one Render() call, which also uploads the image as a texture and
#   draws it with Mesa (llvmpipe under Xvfb; LP_NUM_THREADS is set to the thread count).
#   Neither includes writing PNGs.
# - Threads: multiray splits the frame into tiles pulled by its threads; VTK deals image
#   rows out to its threads (vtkMultiThreader).
set -eu
build=${1:?usage: bench/volume_vs_vtk.sh BUILD_DIR [OUT_DIR]}
out=${2:-bench-out/volume-vs-vtk}
frames=${FRAMES:-20}
warmup=${WARMUP:-2}
repeats=${REPEATS:-3}
threads_list=${THREADS:-"1 2"}
here=$(dirname "$0")
vol="$here/../../shared/data/volumes/aneurism_256x256x256_uint8.nhdr"
mr="$build/src/app/multiray"
py=/usr/bin/python3  # Debian's, where python3-vtk9 lives
# multiray's default view of this volume (stats.json's settings.camera), fixed for both.
cam=-316.8896,452.5656,257.6259,0,0,0,0,0,1,45
if [ ! -f "$vol" ]; then
  echo "volume_vs_vtk.sh: skipped: no $vol (the shared data folder)" >&2
  exit 0
fi
[ -x "$mr" ] || { echo "volume_vs_vtk.sh: no multiray at $mr" >&2; exit 2; }
if ! dpkg -s python3-vtk9 xvfb > /dev/null 2>&1; then
  apt-get update && apt-get install -y python3-vtk9 xvfb
fi
mkdir -p "$out"
for r in $(seq 1 "$repeats"); do
  for t in $threads_list; do
    "$mr" render "$vol" --res 256x192 --tf angio --step 0.5 \
      --devices "cpu:threads=$t" --prepass-stride 0 --frames $((frames + warmup)) --camera="$cam" \
      -o "$out/multiray-t$t-r$r" --overwrite -q
    LP_NUM_THREADS=$t xvfb-run -a "$py" "$here/vtk_volume.py" "$vol" --threads "$t" \
      --frames "$frames" --warmup "$warmup" --res 256x192 --step 0.5 --camera="$cam" \
      --out "$out/vtk-t$t-r$r.png" > "$out/vtk-t$t-r$r.json"
  done
done
last_t=${threads_list##* }
last_mr=$(printf '%s/multiray-t%s-r%s/frame_%04d.png' "$out" "$last_t" "$repeats" $((frames + warmup - 1)))
"$py" - "$out" "$warmup" "$repeats" "$threads_list" <<'PY'
import json, math, sys
out, warmup, repeats, threads = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4].split()

def median_ci(xs):
    """Median and a distribution-free ~95% interval from order statistics (binomial)."""
    xs = sorted(xs)
    n = len(xs)
    med = xs[n // 2] if n % 2 else 0.5 * (xs[n // 2 - 1] + xs[n // 2])
    # The largest k with P(Binomial(n, 1/2) < k) <= 2.5%: [x_(k), x_(n+1-k)] covers >= 95%.
    k, cdf = 0, 0.0
    while k < n:
        p = math.comb(n, k) / 2 ** n
        if cdf + p > 0.025:
            break
        cdf += p
        k += 1
    if k == 0:
        return med, float("nan"), float("nan")  # under 6 frames: no 95% interval
    return med, xs[k - 1], xs[n - k]

print(f"{'threads':>7}  {'multiray ms [95%]':>26}  {'VTK ms [95%]':>26}  {'multiray/VTK':>12}")
for t in threads:
    mr, vt = [], []
    for r in range(1, repeats + 1):
        stats = json.load(open(f"{out}/multiray-t{t}-r{r}/stats.json"))
        mr += [f["frame_ms"] for f in stats["frames"][warmup:]]
        vt += json.load(open(f"{out}/vtk-t{t}-r{r}.json"))["frame_ms"]
    m, ml, mh = median_ci(mr)
    v, vl, vh = median_ci(vt)
    iv = lambda lo, hi: "[    n/a,     n/a]" if math.isnan(lo) else f"[{lo:7.2f}, {hi:7.2f}]"
    print(f"{t:>7}  {m:8.2f} {iv(ml, mh)}  {v:8.2f} {iv(vl, vh)}  {m / v:12.3f}")
print(f"({len(mr)} multiray and {len(vt)} VTK frames per row, pooled over {repeats} repeats)")
PY
echo "image (multiray | VTK's ray-cast image, last repeat at $last_t threads):"
"$py" "$here/image_diff.py" "$last_mr" "$out/vtk-t$last_t-r$repeats.png" \
  --side-by-side "$out/side_by_side.png"
echo "side by side: $out/side_by_side.png"
