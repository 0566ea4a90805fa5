// The volume raycaster of Bruder, Frey & Ertl 2017 ("Prediction-based load balancing and
// resolution tuning for interactive volume raycasting", §3): per pixel one ray, marched
// front to back at a fixed step, transfer-function colour and opacity per sample, shading
// from central-difference gradients with a headlight (7 volume fetches per sample, the
// cost the paper's model counts), early ray termination at an accumulated opacity of
// 0.99, and object-order empty-space skipping over 16^3-voxel blocks.
//
// Every sample of a ray lies on one lattice, t_k = t_entry + k * step, fixed by the ray
// alone: skipping an empty block drops only samples whose opacity is exactly zero, so the
// image is bit-identical with and without skipping, and for any split of the image.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "render/kernel.h"
#include "render/shared/language.h"
#include "render/skip_cells.h"
#include "render/voxel_grid.h"
#include "volume/blocks.h"
#include "volume/transfer_function.h"
#include "volume/volume.h"

namespace multiray {

// The volume as the raycaster needs it (representation "volume" in the SceneCache): the
// grid and its block histograms, built once when the volume loads.
struct VolumeScene {
  explicit VolumeScene(const Volume& v)
      : volume(v),
        blocks(build_blocks(v)),
        voxels(make_voxel_grid(v)),
        cells(build_skip_cells(v)) {}
  const Volume& volume;
  VolumeBlocks blocks;
  VoxelGrid voxels;  // the CPU raycaster's copy in the file's type (render/voxel_grid.h)
  SkipCells cells;   // the CPU raycaster's finer empty-space skipping (render/skip_cells.h)
};

// How a frame shows the volume: the transfer function baked for the kernel, the block
// opacities that drive empty-space skipping, and the ray step. Built once per transfer
// function (make_volume_style) and shared by every device of the frames that use it.
struct VolumeStyle {
  std::string tf_name;
  TransferTable table;  // RGBA over data values; alpha per `reference_step`
  // Per table entry: linear RGB and log(1 - alpha), so a sample's opacity at any step is
  // 1 - exp(log(1 - alpha) * step / reference_step) (opacity correction, Engel et al.,
  // "Real-Time Volume Graphics" §1.4.3) without a pow per sample.
  // The OpenCL raycaster uploads it as is (float4); render/shared/transfer.h reads it.
  std::vector<mr_float4> colour_log_transparency;
  float reference_step = 1;  // voxel lengths
  BlockOpacity opacity;      // per block of VolumeScene::blocks
  // Per block: the share of its voxels the transfer function gives a non-zero opacity
  // (from the density histograms; conservative). The raycaster shades (6 more fetches)
  // only such samples, so this is what makes a sample cost 1 or 7 fetches.
  std::vector<float> shaded_fraction;
  float step = 0.5f;            // ray step in voxel lengths, before RenderSettings::step_scale
  float ert_threshold = 0.99f;  // early ray termination; > 1 turns it off
  bool skip_empty = true;       // empty-space skipping (never changes the image)
  // Per cell of VolumeScene::cells: the largest opacity the table gives there (0: empty).
  // The CPU raycaster skips such cells inside non-empty blocks; empty: blocks only.
  std::vector<float> cell_max_opacity;
  Vec3 background{0, 0, 0};  // radiance behind the volume
};

// The style for `tf` (resolved to data units) on `vs`; `step` in voxel lengths.
std::shared_ptr<VolumeStyle> make_volume_style(const VolumeScene& vs, const TransferFunction& tf,
                                               float step);

// The part of `ray` that crosses non-empty blocks: [front, back] in ray parameter (world
// distance for a unit direction), Bruder's D_front and D_back; front > back when the ray
// meets no non-empty block.
struct RaySpan {
  float front = 1, back = 0;
  bool empty() const { return front > back; }
};
RaySpan non_empty_span(const VolumeScene& vs, const BlockOpacity& opacity, const Ray& ray);

class VolumeRaycaster : public Kernel {
 public:
  explicit VolumeRaycaster(const VolumeScene& vs) : vs_(vs) {}
  // Needs settings.volume_style; throws std::invalid_argument without one.
  KernelStats render_rect(const ViewSetup& view, const RenderSettings& settings, Rect rect,
                          Framebuffer& out) const override;
  // One ray's composited radiance; `steps` counts the samples taken.
  Vec3 cast(const Ray& ray, const VolumeStyle& style, float step_scale, uint64_t& steps) const;

 private:
  const VolumeScene& vs_;
};

// The SceneCache's "volume" representation of its scene (which must hold a volume).
const VolumeScene& volume_scene(SceneCache& scenes);
std::unique_ptr<Kernel> make_volume_raycaster(SceneCache& scenes, bool compact);

}  // namespace multiray
