// The integrator written once for every backend (render/shared/path.h), tested on its own:
// since the CPU and OpenCL run the same source, their match tests can no longer see a
// mistake in it, so the sample dimensions each step draws are checked here directly.
#include <gtest/gtest.h>

#include "render/render_types.h"
#include "render/shared/path.h"
#include "scene/builders.h"

namespace multiray {
namespace {

// A path at depth `depth` leaving a surface at the origin facing +z, seen from above.
struct Bounce {
  explicit Bounce(int depth) {
    path_init(&path, sample_stream_for_path(7u, 3u, 1u, 0u, 42u));
    path.depth = depth;
    path.ray = make_ray(Vec3(0.3f, 0.2f, 1.0f), normalize(Vec3(-0.3f, -0.2f, -1.0f)), INFINITY);
  }
  PathState path{};
};

// What the BSDF sample must be: drawn from the bounce's block at MR_SOBOL_BSDF_OFFSET, the
// lobe's value first (passed over when there is no choice), then the 2D value.
Vec3 expected_direction(const BsdfParams& bsdf, const Frame& frame, Vec3 wo, int depth,
                        SampleStream u) {
  sample_stream_at_bounce(&u, depth);
  u.dim += MR_SOBOL_BSDF_OFFSET;
  const float u_lobe = sample_1d(&u);  // drawn here either way: its dimension is the lobe's
  const Vec2 u12 = sample_2d(&u);
  BsdfSample bs;
  EXPECT_TRUE(bsdf_sample(&bsdf, wo, bsdf_chooses_lobe(&bsdf) ? u_lobe : 0.0f, u12.x, u12.y, &bs));
  return frame.to_world(bs.wi);
}

void expect_continues_from_the_bsdf_dimensions(const BsdfParams& bsdf) {
  const Scene scene = make_lit_plane(0.5f, 0.0f);
  const RenderScene rs(scene);
  const SceneData sd = rs.scene_data(0.0f, 1e-4f);
  const Frame frame = Frame::from_normal(Vec3(0, 0, 1));
  for (int depth = 0; depth < 3; ++depth) {
    Bounce b(depth);
    const SampleStream start = b.path.u;
    const Vec3 wo = frame.to_local(-b.path.ray.dir);
    path_scatter(&sd, &b.path, &bsdf, &frame, wo, Vec3(0.0f), Vec3(0, 0, 1), PathSettings{8, 8});
    ASSERT_TRUE(b.path.alive) << depth;
    const Vec3 want = expected_direction(bsdf, frame, wo, depth, start);
    EXPECT_EQ(b.path.ray.dir.x, want.x) << depth;
    EXPECT_EQ(b.path.ray.dir.y, want.y) << depth;
    EXPECT_EQ(b.path.ray.dir.z, want.z) << depth;
    EXPECT_EQ(b.path.depth, depth + 1);
  }
}

TEST(PathIntegrator, ADiffuseBounceDrawsItsDirectionPastTheLobesDimension) {
  const BsdfParams diffuse = bsdf_params(Vec3(0.5f), 0.0f, 1.0f, 1.5f, false);
  ASSERT_FALSE(bsdf_chooses_lobe(&diffuse));
  expect_continues_from_the_bsdf_dimensions(diffuse);
}

TEST(PathIntegrator, AHalfMetallicBounceDrawsItsLobeThenItsDirection) {
  const BsdfParams mixed = bsdf_params(Vec3(0.5f), 0.5f, 0.4f, 1.5f, false);
  ASSERT_TRUE(bsdf_chooses_lobe(&mixed));
  expect_continues_from_the_bsdf_dimensions(mixed);
}

}  // namespace
}  // namespace multiray
