#include "render/volume_raycaster.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include "render/path_tracer.h"
#include "render/rng.h"
#include "render/shared/transfer.h"
#include "render/shared/volume.h"
#include "render/volume_march.h"

namespace multiray {

namespace {

// Headlight shading: ambient plus diffuse about the gradient, |cos| so both sides of an
// iso-surface are lit (a common choice in volume raycasters; Bruder et al. do not say).
constexpr float kAmbient = 0.3f, kDiffuse = 0.7f;

// The voxels of one store of a VoxelGrid as render/shared/volume.h reads them.
template <class T>
struct CpuVoxels {
  const T* data;
  int n[3];
  Vec3 spacing;
  size_t nx, nxy;
};

template <class T>
inline float volume_voxel(const CpuVoxels<T>* g, int x, int y, int z) {
  return float(g->data[size_t(z) * g->nxy + size_t(y) * g->nx + size_t(x)]);
}

template <class T>
Vec3 cast_over(const T* data, const Volume& v, const VolumeShading& s, Vec3 background,
               const Ray& ray, uint64_t& steps) {
  const CpuVoxels<T> g{
      data, {v.nx, v.ny, v.nz}, v.spacing, size_t(v.nx), size_t(v.nx) * size_t(v.ny)};
  uint32_t n = 0;
  const Vec3 L = volume_cast(&g, &s, v.lower(), background, ray.org, ray.dir, &n);
  steps += n;
  return L;
}

// Per block, the largest opacity the kernel can see there: the maximum over the table
// entries that interpolation between the block's smallest and largest value reads (one
// entry of margin for rounding). Exact-zero blocks are then provably invisible to the
// kernel, which is what makes skipping them leave the image unchanged; the transfer
// function's own maximum is not enough, since a table entry just outside a block's range
// can be non-zero.
std::vector<float> table_max_opacity(const VolumeBlocks& b, const TransferTable& table) {
  const int last = int(table.rgba.size()) - 1;
  const float to_index = float(last) / std::max(table.hi - table.lo, 1e-30f);
  auto index = [&](float v) { return std::clamp((v - table.lo) * to_index, 0.0f, float(last)); };
  std::vector<float> out(b.min_value.size());
  for (size_t i = 0; i < out.size(); ++i) {
    const int lo = std::max(int(std::floor(index(b.min_value[i]))) - 1, 0);
    const int hi = std::min(int(std::ceil(index(b.max_value[i]))) + 1, last);
    float m = 0;
    for (int k = lo; k <= hi; ++k) m = std::max(m, table.rgba[size_t(k)][3]);
    out[i] = m;
  }
  return out;
}

// Per block, the share of its voxels in density bins where `tf` is not zero.
std::vector<float> shaded_fraction(const VolumeScene& vs, const TransferFunction& tf) {
  std::array<bool, kDensityBins> visible{};
  for (int b = 0; b < kDensityBins; ++b) {
    const auto range = density_bin_range(vs.volume, b);
    visible[size_t(b)] = max_opacity(tf, range[0], range[1]) > 0;
  }
  std::vector<float> out(vs.blocks.count(), 0.0f);
  for (size_t i = 0; i < out.size(); ++i) {
    uint64_t all = 0, shown = 0;
    for (int b = 0; b < kDensityBins; ++b) {
      all += vs.blocks.density[i][size_t(b)];
      if (visible[size_t(b)]) shown += vs.blocks.density[i][size_t(b)];
    }
    out[i] = all > 0 ? float(double(shown) / double(all)) : 0.0f;
  }
  return out;
}

}  // namespace

std::shared_ptr<VolumeStyle> make_volume_style(const VolumeScene& vs, const TransferFunction& tf,
                                               float step) {
  auto style = std::make_shared<VolumeStyle>();
  style->tf_name = tf.name;
  style->table = bake(tf, vs.volume.min_value, vs.volume.max_value);
  style->reference_step = tf.reference_step;
  style->colour_log_transparency.reserve(style->table.rgba.size());
  for (const auto& c : style->table.rgba) {
    const float alpha = std::clamp(c[3], 0.0f, 1.0f);
    // An opacity of 1 would make log(0); 1 - 1e-6 is opaque for any step of interest.
    style->colour_log_transparency.push_back(
        {c[0], c[1], c[2], std::log1p(-std::min(alpha, 1.0f - 1e-6f))});
  }
  style->opacity = block_opacity(vs.blocks, tf, vs.volume);
  style->shaded_fraction = shaded_fraction(vs, tf);
  style->opacity.max_opacity = table_max_opacity(vs.blocks, style->table);
  style->cell_max_opacity = cell_max_opacity(vs.cells, style->table);
  style->step = step;
  return style;
}

RaySpan non_empty_span(const VolumeScene& vs, const BlockOpacity& opacity, const Ray& ray) {
  const VoxelRay r = to_voxels(vs.volume, ray);
  float t0, t1;
  clip_to_grid(vs.volume, r, t0, t1);
  RaySpan span;
  if (!(t0 < t1)) return span;
  walk_blocks(vs.blocks, r, t0, t1, [&](size_t block, float ta, float tb) {
    if (opacity.max_opacity[block] > 0) {
      if (span.empty()) span.front = ta;
      span.back = tb;
    }
    return true;
  });
  return span;
}

Vec3 VolumeRaycaster::cast(const Ray& ray, const VolumeStyle& style, float step_scale,
                           uint64_t& steps) const {
  const Volume& v = vs_.volume;
  const TransferTable& table = style.table;
  VolumeShading s{};
  s.table = style.colour_log_transparency.data();
  s.last = uint32_t(table.rgba.size() - 1);
  s.table_lo = table.lo;
  s.to_index = float(table.rgba.size() - 1) / std::max(table.hi - table.lo, 1e-30f);
  s.dt = style.step * step_scale * v.voxel_length();
  s.ratio = style.step * step_scale / style.reference_step;
  s.ert = style.ert_threshold;
  s.ambient = kAmbient, s.diffuse = kDiffuse;
  s.skip_empty = style.skip_empty;
  s.block_opacity = style.opacity.max_opacity.data();
  s.cell_opacity = style.cell_max_opacity.empty() ? nullptr : style.cell_max_opacity.data();
  s.blocks[0] = vs_.blocks.bx, s.blocks[1] = vs_.blocks.by, s.blocks[2] = vs_.blocks.bz;
  s.cells[0] = vs_.cells.cx, s.cells[1] = vs_.cells.cy, s.cells[2] = vs_.cells.cz;
  const VoxelGrid& g = vs_.voxels;
  switch (g.store) {
    case VoxelGrid::Store::u8:
      return cast_over(g.as<uint8_t>(), v, s, style.background, ray, steps);
    case VoxelGrid::Store::i8:
      return cast_over(g.as<int8_t>(), v, s, style.background, ray, steps);
    case VoxelGrid::Store::u16:
      return cast_over(g.as<uint16_t>(), v, s, style.background, ray, steps);
    case VoxelGrid::Store::i16:
      return cast_over(g.as<int16_t>(), v, s, style.background, ray, steps);
    case VoxelGrid::Store::f32:
      break;
  }
  return cast_over(v.values.data(), v, s, style.background, ray, steps);
}

KernelStats VolumeRaycaster::render_rect(const ViewSetup& view, const RenderSettings& settings,
                                         Rect rect, Framebuffer& out) const {
  if (!settings.volume_style)
    throw std::invalid_argument("the volume kernel needs a transfer function (volume_style)");
  const VolumeStyle& style = *settings.volume_style;
  const PinholeCamera camera(view.camera, view.width, view.height);
  KernelStats stats;
  for (int y = rect.y0; y < rect.y1; ++y)
    for (int x = rect.x0; x < rect.x1; ++x) {
      const uint32_t pixel = uint32_t(y) * uint32_t(view.width) + uint32_t(x);
      const int spp = view.samples_at(pixel, settings);
      Vec3 sum(0.0f);
      for (int s = 0; s < spp; ++s) {
        // One sample: the pixel centre; more: jittered, keyed by (pixel, sample, ...).
        float jx = 0.5f, jy = 0.5f;
        if (spp > 1) {
          Rng rng = Rng::for_path(pixel, view.first_sample + uint32_t(s), view.seed_frame(),
                                  view.view, settings.seed);
          jx = rng.next(), jy = rng.next();
        }
        Ray ray = camera.ray(float(x) + jx, float(y) + jy);
        ray.dir = normalize(ray.dir);
        sum += cast(ray, style, settings.step_scale, stats.steps);
      }
      out.at(x, y) = spp > 0 ? sum * (1.0f / float(spp)) : Vec3(0.0f);
      stats.samples += uint64_t(spp), stats.rays += uint64_t(spp);
    }
  return stats;
}

const VolumeScene& volume_scene(SceneCache& scenes) {
  return scenes.get<VolumeScene>("volume", [](const Scene& s) {
    if (!s.volume) throw std::invalid_argument("the scene holds no volume");
    return std::make_unique<VolumeScene>(*s.volume);
  });
}

std::unique_ptr<Kernel> make_volume_raycaster(SceneCache& scenes, bool /*compact*/) {
  return std::make_unique<VolumeRaycaster>(volume_scene(scenes));
}

}  // namespace multiray
