#include "render/volume_prepass.h"

#include <algorithm>
#include <cmath>

#include <oneapi/tbb/parallel_for.h>

#include "render/path_tracer.h"
#include "render/rng.h"
#include "render/volume_march.h"

namespace multiray {

namespace {

// An opacity drawn from a block's 16-bin histogram: bin b with the probability of its
// share of the block's voxels, at the bin's centre.
float draw_opacity(const std::array<float, 16>& histogram, float u) {
  float total = 0;
  for (float f : histogram) total += f;
  if (!(total > 0)) return 0;
  float acc = 0;
  for (int b = 0; b < 16; ++b) {
    acc += histogram[size_t(b)] / total;
    if (u < acc) return (float(b) + 0.5f) / 16;
  }
  return 15.5f / 16;
}

// The length of [ta, tb) that lies in skip cells the style does not skip (as the CPU
// raycaster walks them: render/skip_cells.h); tb - ta when the style has no cells.
float marched_in_block(const VolumeScene& vs, const VolumeStyle& style, const VoxelRay& r,
                       float ta, float tb) {
  if (style.cell_max_opacity.empty()) return tb - ta;
  const int cells[3] = {vs.cells.cx, vs.cells.cy, vs.cells.cz};
  float inside = 0;
  const float reached = walk_grid<kSkipCell>(cells, r, ta, tb, [&](size_t c, float ca, float cb) {
    if (style.cell_max_opacity[c] > 0) inside += cb - ca;
    return true;
  });
  return inside + (tb - reached);  // a walk cut short at the faces: the rest is marched
}

struct CoarseRay {
  float marched = 0, weighted = 0, front = 1, back = 0;
  int blocks = 0;  // blocks the kernel's walk visits (up to the estimated termination)
};

CoarseRay estimate(const VolumeScene& vs, const VolumeStyle& style, const Ray& ray, Rng& rng) {
  const VoxelRay r = to_voxels(vs.volume, ray);
  float t0, t1;
  clip_to_grid(vs.volume, r, t0, t1);
  CoarseRay out;
  if (!(t0 < t1)) return out;
  const float voxel = vs.volume.voxel_length();
  float alpha = 0, ert = INFINITY, marched = 0, weighted = 0;
  walk_blocks(vs.blocks, r, t0, t1, [&](size_t block, float ta, float tb) {
    if (ert == INFINITY) ++out.blocks;
    if (style.opacity.max_opacity[block] == 0) return true;
    if (out.front > out.back) out.front = ta;
    out.back = tb;
    if (ert < INFINITY) return true;  // the span continues; termination already found
    const float shaded = style.shaded_fraction.empty() ? 1.0f : style.shaded_fraction[block];
    const float cost = (1 + 6 * shaded) / 7;  // per unit length, relative to shaded samples
    // The length the raycaster marches here: the block's non-empty skip cells (all of it
    // without them), so that the prediction follows the samples it really takes.
    const float inside = marched_in_block(vs, style, r, ta, tb);
    const float share = tb > ta ? inside / (tb - ta) : 0.0f;
    marched += inside;
    weighted += inside * cost;
    const float o = draw_opacity(style.opacity.histogram[block], rng.next());
    // Opacity accumulated over the block's segment, then where within it the threshold
    // is crossed (opacity grows exponentially along a homogeneous segment).
    const float length = (tb - ta) / (voxel * style.reference_step);
    const float transparency = std::pow(1 - std::min(o, 0.999999f), length);
    const float after = alpha + (1 - alpha) * (1 - transparency);
    if (after >= style.ert_threshold) {
      const float need = std::log((1 - style.ert_threshold) / (1 - alpha));
      const float per_unit = std::log(1 - std::min(o, 0.999999f));
      ert = ta + (tb - ta) * std::clamp(need / (per_unit * length), 0.0f, 1.0f);
      marched -= (tb - ert) * share;
      weighted -= (tb - ert) * share * cost;
    }
    alpha = after;
    return true;
  });
  out.marched = marched, out.weighted = weighted;
  return out;
}

}  // namespace

VolumePrepass run_prepass(const VolumeScene& vs, const VolumeStyle& style, const ViewSetup& view,
                          int stride, uint64_t seed) {
  VolumePrepass p;
  p.stride = std::max(1, stride);
  p.width = (view.width + p.stride - 1) / p.stride;
  p.height = (view.height + p.stride - 1) / p.stride;
  const size_t n = size_t(p.width) * size_t(p.height);
  p.marched.assign(n, 0), p.front.assign(n, 1), p.back.assign(n, 0), p.blocks.assign(n, 0);
  p.weighted.assign(n, 0);
  const PinholeCamera camera(view.camera, view.width, view.height);
  oneapi::tbb::parallel_for(0, p.height, [&](int cy) {
    for (int cx = 0; cx < p.width; ++cx) {
      const float px = std::min(float(cx * p.stride) + 0.5f * float(p.stride), float(view.width));
      const float py = std::min(float(cy * p.stride) + 0.5f * float(p.stride), float(view.height));
      Ray ray = camera.ray(px, py);
      ray.dir = normalize(ray.dir);
      const uint32_t key = uint32_t(cy) * uint32_t(p.width) + uint32_t(cx);
      Rng rng = Rng::for_path(key, 0, view.frame, view.view, seed ^ 0x9e3779b97f4a7c15ull);
      const CoarseRay c = estimate(vs, style, ray, rng);
      p.marched[key] = c.marched, p.front[key] = c.front, p.back[key] = c.back;
      p.blocks[key] = float(c.blocks), p.weighted[key] = c.weighted;
    }
  });
  for (size_t i = 0; i < n; ++i) {
    p.mean_marched += p.marched[i];
    if (p.front[i] <= p.back[i])
      p.max_depth = std::max(p.max_depth, double(p.back[i] - p.front[i]));
  }
  p.mean_marched /= double(std::max<size_t>(n, 1));
  return p;
}

}  // namespace multiray
