#include "render/volume_raycaster.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include "render/path_tracer.h"
#include "render/rng.h"
#include "render/shared/transfer.h"
#include "render/volume_march.h"

namespace multiray {

namespace {

// Headlight shading: ambient plus diffuse about the gradient, |cos| so both sides of an
// iso-surface are lit (a common choice in volume raycasters; Bruder et al. do not say).
constexpr float kAmbient = 0.3f, kDiffuse = 0.7f;

// Trilinear interpolation at voxel coordinates p (voxel centres at i + 0.5), clamped to
// the grid, of the voxels `at(x, y, z)` returns (as floats: the same for every store).
template <class At>
float trilinear(const Volume& v, const At& at, Vec3 p) {
  const float x = std::clamp(p.x - 0.5f, 0.0f, float(v.nx - 1));
  const float y = std::clamp(p.y - 0.5f, 0.0f, float(v.ny - 1));
  const float z = std::clamp(p.z - 0.5f, 0.0f, float(v.nz - 1));
  const int x0 = std::min(int(x), std::max(v.nx - 2, 0)),
            y0 = std::min(int(y), std::max(v.ny - 2, 0)),
            z0 = std::min(int(z), std::max(v.nz - 2, 0));
  const int x1 = std::min(x0 + 1, v.nx - 1), y1 = std::min(y0 + 1, v.ny - 1),
            z1 = std::min(z0 + 1, v.nz - 1);
  const float fx = x - float(x0), fy = y - float(y0), fz = z - float(z0);
  auto row = [&](int yy, int zz) {
    return at(x0, yy, zz) + (at(x1, yy, zz) - at(x0, yy, zz)) * fx;
  };
  const float a = row(y0, z0) + (row(y1, z0) - row(y0, z0)) * fy;
  const float b = row(y0, z1) + (row(y1, z1) - row(y0, z1)) * fy;
  return a + (b - a) * fz;
}

// World-space gradient by central differences, one voxel to each side (6 fetches).
template <class At>
Vec3 gradient(const Volume& v, const At& at, Vec3 p) {
  const Vec3 dx(1, 0, 0), dy(0, 1, 0), dz(0, 0, 1);
  return Vec3((trilinear(v, at, p + dx) - trilinear(v, at, p - dx)) / (2 * v.spacing.x),
              (trilinear(v, at, p + dy) - trilinear(v, at, p - dy)) / (2 * v.spacing.y),
              (trilinear(v, at, p + dz) - trilinear(v, at, p - dz)) / (2 * v.spacing.z));
}

// The voxel at (x, y, z) of `data` (x fastest) as a float.
template <class T>
struct VoxelAt {
  const T* data;
  size_t nx, nxy;
  float operator()(int x, int y, int z) const {
    return float(data[size_t(z) * nxy + size_t(y) * nx + size_t(x)]);
  }
};

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
  const size_t nx = size_t(v.nx), nxy = size_t(v.nx) * size_t(v.ny);
  const VoxelGrid& g = vs_.voxels;
  switch (g.store) {
    case VoxelGrid::Store::u8:
      return march(ray, style, step_scale, steps, VoxelAt<uint8_t>{g.as<uint8_t>(), nx, nxy});
    case VoxelGrid::Store::i8:
      return march(ray, style, step_scale, steps, VoxelAt<int8_t>{g.as<int8_t>(), nx, nxy});
    case VoxelGrid::Store::u16:
      return march(ray, style, step_scale, steps, VoxelAt<uint16_t>{g.as<uint16_t>(), nx, nxy});
    case VoxelGrid::Store::i16:
      return march(ray, style, step_scale, steps, VoxelAt<int16_t>{g.as<int16_t>(), nx, nxy});
    case VoxelGrid::Store::f32:
      break;
  }
  return march(ray, style, step_scale, steps, VoxelAt<float>{v.values.data(), nx, nxy});
}

template <class At>
Vec3 VolumeRaycaster::march(const Ray& ray, const VolumeStyle& style, float step_scale,
                            uint64_t& steps, const At& at) const {
  const Volume& v = vs_.volume;
  const VoxelRay r = to_voxels(v, ray);
  float t0, t1;
  clip_to_grid(v, r, t0, t1);
  Vec3 colour(0.0f);
  float alpha = 0;
  if (t0 < t1) {
    const float dt = style.step * step_scale * v.voxel_length();
    const float ratio = style.step * step_scale / style.reference_step;
    const TransferTable& table = style.table;
    const uint32_t last = uint32_t(table.rgba.size() - 1);
    const float to_index = float(table.rgba.size() - 1) / std::max(table.hi - table.lo, 1e-30f);
    // The first lattice index at or after t (a function of t alone; see walk_blocks).
    auto first_index = [&](float t) { return int64_t(std::ceil(std::max(t - t0, 0.0f) / dt)); };
    // The samples of [ta, tb): false once the ray is opaque (early termination).
    auto samples = [&](float ta, float tb) {
      for (int64_t k = first_index(ta), end = first_index(tb); k < end; ++k) {
        const Vec3 p = r.org + r.dir * (t0 + float(k) * dt);
        ++steps;
        const float value = trilinear(v, at, p);
        const TfSample tf = tf_lookup(style.colour_log_transparency.data(), last,
                                      tf_position(value, table.lo, to_index, last));
        if (tf.log_t == 0) continue;  // fully transparent: no gradient, no change
        const float a = tf_opacity(tf.log_t, ratio);
        Vec3 c = tf.colour;
        const Vec3 g = gradient(v, at, p);
        const float glen = length(g);
        if (glen > 0) c = c * (kAmbient + kDiffuse * std::abs(dot(g, ray.dir)) / glen);
        colour += c * ((1 - alpha) * a);
        alpha += (1 - alpha) * a;
        if (alpha >= style.ert_threshold) return false;
      }
      return true;
    };
    const bool fine = style.skip_empty && !style.cell_max_opacity.empty();
    const int cells[3] = {vs_.cells.cx, vs_.cells.cy, vs_.cells.cz};
    walk_blocks(vs_.blocks, r, t0, t1, [&](size_t block, float ta, float tb) {
      if (style.skip_empty && style.opacity.max_opacity[block] == 0) return true;
      if (!fine) return samples(ta, tb);
      // Inside a block that is not empty, its 4^3 cells: the empty ones are skipped.
      bool going = true;
      const float reached =
          walk_grid<kSkipCell>(cells, r, ta, tb, [&](size_t c, float ca, float cb) {
            if (style.cell_max_opacity[c] == 0) return true;
            return going = samples(ca, cb);
          });
      // A walk cut short by rounding at the grid's faces leaves the rest unskipped.
      return going && (reached >= tb || samples(reached, tb));
    });
  }
  return colour + style.background * (1 - alpha);
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
