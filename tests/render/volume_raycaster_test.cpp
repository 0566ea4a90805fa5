// The volume raycaster against known answers: a homogeneous slab's transmittance
// exp(-sigma d), the composite of a constant-colour volume, empty-space skipping that
// never changes the image, early ray termination within its threshold, and images that do
// not depend on the split.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <random>

#include "render/path_tracer.h"
#include "render/volume_raycaster.h"
#include "render_helpers.h"

namespace multiray {
namespace volume_raycaster_test {

// nx x ny x nz voxels of `fill(x, y, z)`, spacing 1, centred on the origin.
template <class Fill>
std::shared_ptr<Volume> make_volume(int nx, int ny, int nz, Fill fill) {
  auto v = std::make_shared<Volume>();
  v->name = "synthetic";
  v->nx = nx, v->ny = ny, v->nz = nz;
  v->values.resize(v->voxel_count());
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x)
        v->values[(size_t(z) * size_t(ny) + size_t(y)) * size_t(nx) + size_t(x)] = fill(x, y, z);
  v->min_value = *std::min_element(v->values.begin(), v->values.end());
  v->max_value = *std::max_element(v->values.begin(), v->values.end());
  return v;
}

// Opacity `alpha` (per voxel length) and colour `c` for every value in [lo, hi].
TransferFunction flat_tf(float lo, float hi, Vec3 c, float alpha) {
  TransferFunction tf;
  tf.name = "flat";
  tf.points = {{lo, c, alpha}, {hi, c, alpha}};
  return tf;
}

// A ray along -z through the centre of the volume, from outside.
Ray axis_ray() {
  Ray r;
  r.org = Vec3(0.1f, 0.1f, 100);
  r.dir = Vec3(0, 0, -1);
  return r;
}

TEST(VolumeRaycaster, SlabTransmittanceIsExpMinusSigmaD) {
  // 32 voxels deep along z; sigma = -ln(1 - alpha) per voxel length.
  auto v = make_volume(8, 8, 32, [](int, int, int) { return 1.0f; });
  v->min_value = 0;  // a range for the table; every voxel is 1
  const VolumeScene vs(*v);
  for (float alpha : {0.02f, 0.05f, 0.1f}) {
    for (float step : {0.25f, 0.5f, 1.0f}) {
      auto style = make_volume_style(vs, flat_tf(0, 1, Vec3(0.0f), alpha), step);
      style->background = Vec3(1.0f);  // black medium before white: we see transmittance
      style->ert_threshold = 2;
      uint64_t steps = 0;
      const Vec3 seen = VolumeRaycaster(vs).cast(axis_ray(), *style, 1.0f, steps);
      const double sigma = -std::log(1.0 - alpha), expected = std::exp(-sigma * 32.0);
      EXPECT_NEAR(seen.x, expected, 0.005 * expected) << "alpha " << alpha << " step " << step;
      EXPECT_EQ(steps, uint64_t(std::lround(32 / step)));
    }
  }
}

TEST(VolumeRaycaster, ConstantColourVolumeGivesTheAnalyticComposite) {
  auto v = make_volume(8, 8, 32, [](int, int, int) { return 1.0f; });
  v->min_value = 0;
  const VolumeScene vs(*v);
  const Vec3 c(0.9f, 0.5f, 0.2f), bg(0.1f, 0.2f, 0.3f);
  auto style = make_volume_style(vs, flat_tf(0, 1, c, 0.05f), 0.5f);
  style->background = bg;
  style->ert_threshold = 2;
  uint64_t steps = 0;
  const Vec3 seen = VolumeRaycaster(vs).cast(axis_ray(), *style, 1.0f, steps);
  const float t = std::pow(0.95f, 32.0f);  // transmittance through 32 voxels
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(seen[i], c[i] * (1 - t) + bg[i] * t, 0.005f);
}

TEST(VolumeRaycaster, StepScaleKeepsTheTransmittance) {
  // Opacity correction: a coarser step (frame-time targeting) sees the same medium.
  auto v = make_volume(8, 8, 32, [](int, int, int) { return 1.0f; });
  v->min_value = 0;
  const VolumeScene vs(*v);
  auto style = make_volume_style(vs, flat_tf(0, 1, Vec3(0.0f), 0.1f), 0.5f);
  style->background = Vec3(1.0f);
  uint64_t fine = 0, coarse = 0;
  const VolumeRaycaster k(vs);
  const float a = k.cast(axis_ray(), *style, 1.0f, fine).x;
  const float b = k.cast(axis_ray(), *style, 4.0f, coarse).x;
  EXPECT_NEAR(a, b, 0.005f * a);
  EXPECT_EQ(fine, 4 * coarse);
}

// A ball of value 200 in a 48 x 40 x 36 field of zeros (several partial blocks), seen
// through a transfer function that hides values below 50.
struct BallScene {
  BallScene()
      : volume(make_volume(48, 40, 36, [](int x, int y, int z) {
          const float dx = float(x) - 30, dy = float(y) - 18, dz = float(z) - 17;
          return dx * dx + dy * dy + dz * dz < 100 ? 200.0f : 0.0f;
        })) {
    scene.name = "ball";
    scene.volume = volume;
    Camera cam;
    cam.eye = Vec3(20, 30, 80);
    cam.target = Vec3(0, 0, 0);
    scene.cameras.push_back(cam);
    TransferFunction tf;
    tf.name = "ball";
    tf.points = {{0, Vec3(0.0f), 0}, {50, Vec3(0.0f), 0}, {200, Vec3(1, 0.8f, 0.6f), 0.3f}};
    vs = std::make_unique<VolumeScene>(*volume);
    style = make_volume_style(*vs, tf, 0.5f);
  }
  std::shared_ptr<Volume> volume;
  Scene scene;
  std::unique_ptr<VolumeScene> vs;
  std::shared_ptr<VolumeStyle> style;
};

Framebuffer render(const BallScene& b, const std::vector<Rect>& rects, int devices = 1) {
  RenderSettings s;
  s.kernel = "volume";
  s.spp = 1;
  s.volume_style = b.style;
  return testing::render_regions(b.scene, 41, 29, s, rects, devices);
}

bool same_bits(const Framebuffer& a, const Framebuffer& b) {
  return a.pixels.size() == b.pixels.size() &&
         std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(Vec3)) == 0;
}

TEST(VolumeRaycaster, EmptySpaceSkippingNeverChangesTheImage) {
  BallScene b;
  uint64_t with = 0, without = 0;
  const VolumeRaycaster k(*b.vs);
  const PinholeCamera cam(b.scene.cameras[0], 41, 29);
  int lit = 0;
  for (int y = 0; y < 29; ++y)
    for (int x = 0; x < 41; ++x) {
      Ray r = cam.ray(x + 0.5f, y + 0.5f);
      r.dir = normalize(r.dir);
      b.style->skip_empty = true;
      const Vec3 a = k.cast(r, *b.style, 1, with);
      b.style->skip_empty = false;
      const Vec3 c = k.cast(r, *b.style, 1, without);
      ASSERT_EQ(std::memcmp(&a, &c, sizeof a), 0) << x << "," << y;
      lit += a.x > 0;
    }
  EXPECT_GT(lit, 20);            // the ball is in view
  EXPECT_LT(with, without / 2);  // and most of the marching was skipped
}

// The CPU raycaster reads 8- and 16-bit volumes in their own type (render/voxel_grid.h):
// only when every value fits exactly, and with the same image as from the floats.
TEST(VoxelGrid, KeepsTheFileTypeOnlyWhenEveryValueFitsIt) {
  auto v = make_volume(4, 3, 2, [](int x, int y, int z) { return float(x + 4 * y + 12 * z); });
  v->type = VoxelType::u8;
  EXPECT_EQ(make_voxel_grid(*v).store, VoxelGrid::Store::u8);
  EXPECT_EQ(make_voxel_grid(*v).bytes.size(), v->voxel_count());
  v->values[5] = 0.5f;  // not an integer
  EXPECT_EQ(make_voxel_grid(*v).store, VoxelGrid::Store::f32);
  v->values[5] = 256;  // past uint8
  EXPECT_EQ(make_voxel_grid(*v).store, VoxelGrid::Store::f32);
  v->type = VoxelType::u16;
  EXPECT_EQ(make_voxel_grid(*v).store, VoxelGrid::Store::u16);
  v->values[5] = -1024;
  EXPECT_EQ(make_voxel_grid(*v).store, VoxelGrid::Store::f32);
  v->type = VoxelType::i16;
  const VoxelGrid g = make_voxel_grid(*v);
  ASSERT_EQ(g.store, VoxelGrid::Store::i16);
  EXPECT_EQ(g.as<int16_t>()[5], -1024);
  v->values[0] = 1e9f;
  EXPECT_EQ(make_voxel_grid(*v).store, VoxelGrid::Store::f32);
}

TEST(VolumeRaycaster, ANarrowStoreGivesTheImageOfTheFloats) {
  for (VoxelType type : {VoxelType::u8, VoxelType::i16}) {
    BallScene b;
    if (type == VoxelType::i16)  // negative values too, in a 16-bit signed volume
      for (float& x : b.volume->values) x = x > 0 ? 3000.0f : -1000.0f;
    b.volume->type = type;
    const VolumeScene narrow(*b.volume);
    VolumeScene wide(*b.volume);
    wide.voxels = VoxelGrid{};  // read Volume::values
    ASSERT_NE(narrow.voxels.store, VoxelGrid::Store::f32);
    TransferFunction tf;
    tf.name = "ball";
    tf.points = {{-1000, Vec3(0.0f), 0}, {100, Vec3(0.0f), 0}, {3000, Vec3(1, 0.8f, 0.6f), 0.3f}};
    auto style = make_volume_style(narrow, tf, 0.5f);
    const VolumeRaycaster a(narrow), c(wide);
    const PinholeCamera cam(b.scene.cameras[0], 41, 29);
    uint64_t steps = 0;
    int lit = 0;
    for (int y = 0; y < 29; ++y)
      for (int x = 0; x < 41; ++x) {
        Ray r = cam.ray(x + 0.5f, y + 0.5f);
        r.dir = normalize(r.dir);
        const Vec3 p = a.cast(r, *style, 1, steps), q = c.cast(r, *style, 1, steps);
        ASSERT_EQ(std::memcmp(&p, &q, sizeof p), 0) << x << "," << y;
        lit += p.x > 0;
      }
    EXPECT_GT(lit, 20);
  }
}

// The 4^3 skip cells: each cell's opacity is the largest table entry its value range
// (apron included) can read, as a scan of the voxels and entries finds it.
TEST(SkipCells, EachCellsOpacityIsTheLargestItsVoxelsCanRead) {
  std::mt19937 rng(3);
  // Mostly 0-2 with rare spikes of 150: cells' ranges differ, and so do their aprons'.
  auto v = make_volume(
      19, 13, 9, [&](int, int, int) { return rng() % 150 == 0 ? 150.0f : float(rng() % 3); });
  const SkipCells cells = build_skip_cells(*v);
  ASSERT_EQ(cells.cx, 5);
  ASSERT_EQ(cells.cz, 3);
  TransferTable table;
  table.lo = 0, table.hi = 199;
  for (int i = 0; i < 97; ++i) table.rgba.push_back({0, 0, 0, i > 48 ? float(i) : 0.0f});
  const std::vector<float> got = cell_max_opacity(cells, table);
  const float to_index = 96.0f / 199.0f;
  int spiked = 0, quiet = 0;
  for (int kz = 0; kz < cells.cz; ++kz)
    for (int ky = 0; ky < cells.cy; ++ky)
      for (int kx = 0; kx < cells.cx; ++kx) {
        float lo = INFINITY, hi = -INFINITY;  // the voxels of the cell and its apron
        for (int z = std::max(4 * kz - 1, 0); z < std::min(4 * kz + 5, v->nz); ++z)
          for (int y = std::max(4 * ky - 1, 0); y < std::min(4 * ky + 5, v->ny); ++y)
            for (int x = std::max(4 * kx - 1, 0); x < std::min(4 * kx + 5, v->nx); ++x) {
              const float value = v->values[(size_t(z) * 13 + size_t(y)) * 19 + size_t(x)];
              lo = std::min(lo, value), hi = std::max(hi, value);
            }
        const int a = std::max(int(std::floor(lo * to_index)) - 1, 0);
        const int b = std::min(int(std::ceil(hi * to_index)) + 1, 96);
        float want = 0;
        for (int k = a; k <= b; ++k) want = std::max(want, table.rgba[size_t(k)][3]);
        const float seen =
            got[(size_t(kz) * size_t(cells.cy) + size_t(ky)) * size_t(cells.cx) + size_t(kx)];
        EXPECT_EQ(seen, want) << kx << "," << ky << "," << kz;
        spiked += hi == 150, quiet += want == 0;
      }
  EXPECT_GT(spiked, 10);  // both kinds of cells were checked
  EXPECT_GT(quiet, 10);
}

TEST(VolumeRaycaster, SkipCellsSkipMoreAndChangeNothing) {
  BallScene b;
  const VolumeRaycaster k(*b.vs);
  auto blocks_only = std::make_shared<VolumeStyle>(*b.style);
  blocks_only->cell_max_opacity.clear();
  ASSERT_FALSE(b.style->cell_max_opacity.empty());
  const PinholeCamera cam(b.scene.cameras[0], 41, 29);
  uint64_t fine = 0, coarse = 0;
  int lit = 0;
  for (int y = 0; y < 29; ++y)
    for (int x = 0; x < 41; ++x) {
      Ray r = cam.ray(x + 0.5f, y + 0.5f);
      r.dir = normalize(r.dir);
      const Vec3 a = k.cast(r, *b.style, 1, fine), c = k.cast(r, *blocks_only, 1, coarse);
      ASSERT_EQ(std::memcmp(&a, &c, sizeof a), 0) << x << "," << y;
      lit += a.x > 0;
    }
  EXPECT_GT(lit, 20);
  EXPECT_LT(fine, coarse * 3 / 4);  // the ball fills few of its blocks' cells
}

TEST(VolumeRaycaster, EarlyTerminationStaysWithinItsThreshold) {
  BallScene b;
  b.style->background = Vec3(0.5f);
  const VolumeRaycaster k(*b.vs);
  const PinholeCamera cam(b.scene.cameras[0], 41, 29);
  uint64_t with = 0, without = 0;
  float worst = 0;
  for (int y = 0; y < 29; ++y)
    for (int x = 0; x < 41; ++x) {
      Ray r = cam.ray(x + 0.5f, y + 0.5f);
      r.dir = normalize(r.dir);
      b.style->ert_threshold = 0.99f;
      const Vec3 a = k.cast(r, *b.style, 1, with);
      b.style->ert_threshold = 2;
      const Vec3 c = k.cast(r, *b.style, 1, without);
      for (int i = 0; i < 3; ++i) worst = std::max(worst, std::abs(a[i] - c[i]));
    }
  // What ERT drops is behind an opacity of 0.99: at most 1% of the brightest colour.
  EXPECT_LE(worst, 0.01f);
  EXPECT_LT(with, without);
}

TEST(VolumeRaycaster, ImageDoesNotDependOnTheSplit) {
  BallScene b;
  const Framebuffer whole = render(b, {{0, 0, 41, 29}});
  const Framebuffer split =
      render(b, {{0, 0, 7, 29}, {7, 0, 41, 3}, {7, 3, 30, 29}, {30, 3, 41, 29}}, 3);
  EXPECT_TRUE(same_bits(whole, split));
  float sum = 0;
  for (const Vec3& p : whole.pixels) sum += p.x;
  EXPECT_GT(sum, 1.0f);  // not an empty image
}

TEST(VolumeRaycaster, RefusesAFrameWithoutTransferFunction) {
  BallScene b;
  const VolumeRaycaster k(*b.vs);
  ViewSetup view;
  view.camera = b.scene.cameras[0];
  view.width = 4, view.height = 4;
  Framebuffer fb(4, 4);
  EXPECT_THROW(k.render_rect(view, RenderSettings{}, Rect{0, 0, 4, 4}, fb), std::invalid_argument);
}

}  // namespace volume_raycaster_test
}  // namespace multiray
