// Spatial reprojection for light-field grids (Leria et al., §6.3 and Tables 1-2): the
// reference view (the grid's centre) is path-traced; every other view takes the colour of
// each pixel whose surface the reference also sees, found by moving the reference's
// pixels to that view by their depth (forward warping with a depth test, the nearest
// surface winning). What no reference pixel reaches is a disocclusion, a *hole*. The paper
// leaves holes unfilled; we path-trace them (hole_sample_map gives them the frame's samples
// and every other pixel none), so they are balanced across devices like any other work and
// come out as in a full render of that view.
//
// A surface seen at a slant in the target spreads over more pixels than in the reference,
// and point landings alone would leave gaps in it. So neighbouring reference pixels on one
// surface (depths within a tolerance) also fill the target pixels between their landings,
// along rows and along columns, with interpolated depth: the reference's depth map is
// warped as a surface, not as points. Anything else unreached is a hole.
//
// Limits (docs/multiview.md): colours are the reference's, so view-dependent shading
// (glossy highlights, reflections) is the centre view's; a surface the target sees in
// front of one the reference sees, but which is hidden from the reference, is not
// detected. Leria et al. compute a G-buffer for every target view (80 for 9x9) and know
// each target pixel's surface; we warp without the targets' G-buffers, saving about a
// primary ray per target pixel, and miss that case.
#pragma once

#include <cstdint>
#include <vector>

#include "core/image.h"
#include "render/gbuffer.h"
#include "render/render_types.h"

namespace multiray {

struct ReprojectionOptions {
  // Neighbouring reference pixels lie on one surface when their depths differ by at most
  // this fraction of the nearer; the target pixels between their landings are then filled.
  float depth_tolerance = 0.03f;
};

// For each pixel of a target view (row-major), the reference pixel whose colour it takes
// (reference k's pixel i is k * width * height + i), or kHole.
struct ReprojectionMap {
  static constexpr int32_t kHole = -1;
  int width = 0, height = 0;
  std::vector<int32_t> source;
  size_t holes() const;
};

// Where the reference's pixels land in `target` (same image size as `reference`).
// `reference_depth` is the reference's G-buffer (view-space depth at pixel centres,
// infinity where the ray leaves the scene: such pixels are never moved, so the sky a
// target sees is a hole, one cheap ray each). Pure function.
ReprojectionMap reproject_view(const GBuffer& reference_depth, const ViewSetup& reference,
                               const ViewSetup& target, const ReprojectionOptions& o = {});

// A reference prepared once a frame for all the views warped from it: each pixel's
// surface point (world space) and which neighbours lie on one surface with it (depths
// within the tolerance, or one plane: the same normal and the step between them in it).
// Keeps a pointer to `view`, which must outlive it.
struct ReferenceSurface {
  static constexpr uint8_t kHit = 1, kJoinedRight = 2, kJoinedBelow = 4;
  const ViewSetup* view = nullptr;
  std::vector<Vec3> point;     // valid where flags has kHit
  std::vector<uint8_t> flags;  // per pixel, row-major
};
ReferenceSurface prepare_reference(const GBuffer& depth, const ViewSetup& view,
                                   const ReprojectionOptions& o = {});

// The same from several references (same image size), warped in the order given (nearest
// to the target first): a pixel the first reached keeps its source unless a later one
// brings a surface nearer by more than the depth tolerance. At most 2^31 reference pixels
// in all. `o` must be the options the references were prepared with.
ReprojectionMap reproject_view(const std::vector<const ReferenceSurface*>& references,
                               const ViewSetup& target, const ReprojectionOptions& o = {});

// Where world point `p` appears in `view`: image position in pixels (x right, y down; may
// lie outside the image). False when the point is not in front of the camera.
bool project_to_image(const ViewSetup& view, const Vec3& p, float& px, float& py);

// `spp` samples for every hole, 0 elsewhere (ViewSetup::spp_map). spp in 1..255.
std::vector<uint8_t> hole_sample_map(const ReprojectionMap& map, int spp);

// Copies the references' colours (in the order the map was made with) into every pixel
// of `target` that is not a hole.
void fill_reprojected(const std::vector<const Framebuffer*>& references,
                      const ReprojectionMap& map, Framebuffer& target);

// A frame's reprojection: which views are references (path-traced in full) and each
// view's map (empty for the references). Every map's sources name references by their
// position in `references`.
struct ReprojectedFrame {
  std::vector<uint32_t> references;
  std::vector<ReprojectionMap> maps;
  bool is_reference(size_t view) const;
  // Fills every view but the references from the references' images.
  void fill(std::vector<Framebuffer>& images) const;
  // Holes over the pixels of the views that are not references, in [0, 1].
  double hole_fraction() const;
};

}  // namespace multiray
