// The OpenCL backend on its own: analytic scenes, split independence, the kernel cache,
// build errors, device specs and the host-side BVH.
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <set>

#include "core/error.h"
#include "device/device_factory.h"
#include "device/opencl/cl_program.h"
#include "opencl_helpers.h"
#include "render/flat_bvh.h"
#include "scene/builders.h"

namespace multiray {
namespace opencl_render_test {

using testing::render_on;
using testing::render_whole;
using testing::view_of;

bool same_bits(const Framebuffer& a, const Framebuffer& b) {
  return a.pixels.size() == b.pixels.size() &&
         std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(Vec3)) == 0;
}

// White furnace, as the CPU test: every pixel is Le / (1 - albedo) within 1%.
TEST(OpenClFurnace, EveryPixelEqualsLeOverOneMinusAlbedo) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  for (float albedo : {0.5f, 0.8f}) {
    const Scene scene = make_furnace_sphere(albedo, 1.0f);
    SceneCache rs(scene);
    OpenClDevice device(rs, {}, "opencl:0");
    RenderSettings s;
    s.spp = 256;
    s.max_bounces = albedo > 0.6f ? 80 : 40;
    s.rr_start = 1 << 20;
    const Framebuffer fb = render_whole(device, view_of(scene, 8, 8), s);
    const float expected = 1.0f / (1.0f - albedo);
    for (const Vec3& p : fb.pixels)
      for (int c = 0; c < 3; ++c)
        ASSERT_NEAR(p[c], expected, 0.01f * expected) << "albedo " << albedo;
  }
}

// A diffuse plane under a constant sky: albedo x sky, with no noise at all.
TEST(OpenClLitPlane, RadianceIsAlbedoTimesSky) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  const Scene scene = make_lit_plane(0.5f, 2.0f);
  SceneCache rs(scene);
  OpenClDevice device(rs, {}, "opencl:0");
  const Framebuffer fb =
      render_whole(device, view_of(scene, 24, 16), RenderSettings{.spp = 4, .max_bounces = 4});
  for (const Vec3& p : fb.pixels)
    for (int c = 0; c < 3; ++c) ASSERT_NEAR(p[c], 1.0f, 1e-4f);
}

// The image is a pure function of the pixel: one region or many, one launch or many small
// ones, any work-group size, one device or two pulling concurrently, bit for bit.
TEST(OpenClSplit, ImageIsBitIdenticalForAnySplit) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  const Scene scene = make_cornell_box();
  SceneCache rs(scene);
  const int w = 37, h = 23;
  const ViewSetup view = view_of(scene, w, h, 3);
  const RenderSettings s{.spp = 2, .max_bounces = 5, .seed = 7};
  OpenClDevice a(rs, {}, "opencl:0");
  const Framebuffer whole = render_whole(a, view, s);

  std::vector<Rect> tiles;
  for (int y = 0; y < h; y += 5)
    for (int x = 0; x < w; x += 7) tiles.push_back({x, y, std::min(w, x + 7), std::min(h, y + 5)});
  EXPECT_TRUE(same_bits(render_on({&a}, view, s, tiles), whole)) << "tiles";

  OpenClDevice b(rs, OpenClDeviceOptions{.tile = 4, .work_group = 1}, "opencl:0:tile=4:wg=1");
  EXPECT_TRUE(same_bits(render_whole(b, view, s), whole)) << "tile=4 wg=1";
  EXPECT_TRUE(same_bits(render_on({&a, &b}, view, s, tiles), whole)) << "two devices";
}

// What the kernel does not implement is refused before any work is taken, so the engine
// can hand the whole frame to the other devices.
TEST(OpenClDevice, RefusesAmbientOcclusionWithoutTakingWork) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  const Scene scene = make_cornell_box();
  SceneCache rs(scene);
  OpenClDevice device(rs, {}, "opencl:0");
  std::vector<Framebuffer> out{Framebuffer(8, 8)};
  FrameJob job{{view_of(scene, 8, 8)}, RenderSettings{.kernel = "ao"}, &out};
  ListWorkSource source({WorkItem{{0, 0, 8, 8}, 0}});
  const DeviceReport r = device.render(job, source, 0);
  EXPECT_TRUE(r.failed);
  EXPECT_NE(r.error.find("cannot run the ao kernel"), std::string::npos) << r.error;
  uint32_t id;
  EXPECT_TRUE(source.next(0, id));  // the unit is still there
}

// The second device built from the same source loads the kernel binary from the disk cache.
TEST(OpenClProgram, KernelBinaryIsCachedOnDisk) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  const std::string dir =
      ::testing::TempDir() + "/multiray_cl_cache_" + std::to_string(::getpid());
  std::filesystem::remove_all(dir);
  const char* old = std::getenv("XDG_CACHE_HOME");
  const std::string saved = old ? old : "";
  setenv("XDG_CACHE_HOME", dir.c_str(), 1);
  const Scene scene = make_cornell_box();
  SceneCache rs(scene);
  {
    OpenClDevice first(rs, {}, "opencl:0");
    EXPECT_FALSE(first.kernel_from_cache());
    OpenClDevice second(rs, {}, "opencl:0");
    EXPECT_TRUE(second.kernel_from_cache());
  }
  int files = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir + "/multiray"))
    files += e.path().extension() == ".bin";
  // One binary per size built: two where the kernel allowed fewer than the default 64
  // work-items per group and was rebuilt smaller (rusticl on llvmpipe: 32).
  EXPECT_EQ(files, OpenClDevice(rs, {}, "opencl:0").work_group_size("path") < 64 ? 2 : 1);
  if (old)
    setenv("XDG_CACHE_HOME", saved.c_str(), 1);
  else
    unsetenv("XDG_CACHE_HOME");
  std::filesystem::remove_all(dir);
}

// A compile error names the device and shows the compiler's log.
TEST(OpenClProgram, BuildErrorShowsTheCompilerLog) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  const cl::Device device = cl_util::all_devices().at(0);
  const cl::Context context(device);
  try {
    cl_util::build_program(context, device, "__kernel void k() { undeclared_thing = 1; }", "");
    FAIL() << "expected a DeviceError";
  } catch (const DeviceError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("build failed"), std::string::npos) << msg;
    EXPECT_NE(msg.find("undeclared_thing"), std::string::npos) << msg;
  }
}

TEST(OpenClSpec, ParsesIndexAndKeys) {
  const auto specs =
      parse_device_specs("cpu,opencl,opencl:1:speed=0.5:wg=32:tile=64:fail_after=3");
  ASSERT_EQ(specs.size(), 3u);
  EXPECT_EQ(specs[1].type, "opencl");
  EXPECT_EQ(specs[1].options.count("index"), 0u);
  EXPECT_EQ(specs[2].options.at("index"), "1");
  EXPECT_EQ(specs[2].options.at("wg"), "32");
  EXPECT_THROW(parse_device_specs("opencl:0:threads=2"), InputError);  // a cpu key
  EXPECT_THROW(parse_device_specs("opencl:0:wg"), InputError);
}

TEST(OpenClSpec, MissingDeviceIsAClearError) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  const Scene scene = make_cornell_box();
  SceneCache rs(scene);
  try {
    create_devices("opencl:999", rs);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no OpenCL device 999"), std::string::npos) << e.what();
  }
  EXPECT_THROW(create_devices("opencl:0:speed=2", rs), InputError);
  EXPECT_THROW(create_devices("opencl:0:wg=0", rs), InputError);
}

// Host-only: every non-degenerate triangle is in exactly one leaf, each leaf's triangles
// lie inside the box its parent keeps for it, and each child node's boxes inside its own.
TEST(FlatBvh, HoldsEveryTriangleOnceInsideItsBoxes) {
  const Scene scene = make_cornell_box();
  const FlatBvh bvh = build_flat_bvh(scene);
  ASSERT_FALSE(bvh.nodes.empty());
  EXPECT_LE(bvh.depth, kMaxBvhDepth);
  auto inside = [](Vec3 p, const float lo[3], const float hi[3]) {
    for (int a = 0; a < 3; ++a)
      if (!(p[a] >= lo[a] && p[a] <= hi[a])) return false;
    return true;
  };
  std::multiset<uint32_t> seen;
  for (const FlatNode& n : bvh.nodes)
    for (int c = 0; c < 2; ++c) {
      const uint32_t ref = n.child[c];
      if (ref & kLeafBit) {
        const uint32_t first = (ref & ~kLeafBit) >> kLeafCountBits;
        const uint32_t count = (ref & (kMaxLeafTriangles - 1)) + 1;
        ASSERT_LE(first + count, bvh.triangles.size());
        for (uint32_t i = first; i < first + count; ++i) {
          seen.insert(bvh.triangles[i].prim);
          for (uint32_t k = 0; k < 3; ++k)
            EXPECT_TRUE(inside(scene.positions[scene.indices[3 * bvh.triangles[i].prim + k]],
                               n.lo[c], n.hi[c]));
        }
      } else {
        ASSERT_LT(ref, bvh.nodes.size());
        for (int g = 0; g < 2; ++g) {
          const FlatNode& child = bvh.nodes[ref];
          EXPECT_TRUE(
              inside(Vec3(child.lo[g][0], child.lo[g][1], child.lo[g][2]), n.lo[c], n.hi[c]));
          EXPECT_TRUE(
              inside(Vec3(child.hi[g][0], child.hi[g][1], child.hi[g][2]), n.lo[c], n.hi[c]));
        }
      }
    }
  size_t hittable = 0;
  for (size_t t = 0; t < scene.triangle_count(); ++t) {
    const Vec3 a = scene.positions[scene.indices[3 * t]],
               b = scene.positions[scene.indices[3 * t + 1]],
               c = scene.positions[scene.indices[3 * t + 2]];
    const Vec3 n = cross(b - a, c - a);
    hittable += !(n.x == 0 && n.y == 0 && n.z == 0);
  }
  EXPECT_EQ(seen.size(), hittable);  // no triangle twice...
  EXPECT_EQ(std::set<uint32_t>(seen.begin(), seen.end()).size(), hittable);  // ...none missing
}

// A scene small enough to be one leaf gets a root holding that leaf twice (OpenClLitPlane
// renders such a scene).
TEST(FlatBvh, SingleLeafBecomesARootHoldingItTwice) {
  const Scene scene = make_lit_plane(0.5f, 2.0f);
  const FlatBvh bvh = build_flat_bvh(scene);
  ASSERT_EQ(bvh.nodes.size(), 1u);
  EXPECT_EQ(bvh.nodes[0].child[0], bvh.nodes[0].child[1]);
}

}  // namespace opencl_render_test
}  // namespace multiray
