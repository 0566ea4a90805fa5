// Balancing a part of a frame: one level of a hierarchy. Harada's distributed split
// (GPU Pro 7, Fig. 4.5) gives each machine a band of the frame and lets each machine
// split its band across its own GPUs in the other direction; an MPI rank with several
// local devices does the same with each part the master gives it. RegionBalancer lets any
// balancer do that: it plans the region as if it were a whole frame (a frame of the
// region's size, weights cropped, optionally transposed) and moves the items into place;
// measurements are moved back before the inner balancer learns from them.
#pragma once

#include <memory>
#include <string>

#include "balance/balancer.h"

namespace multiray::balance {

// `shape` cut to `region` (clipped to the frame): the region's size, the same views, the
// weights of the region's pixels. Throws std::invalid_argument for an empty region.
FrameShape crop_shape(const FrameShape& shape, const Rect& region);
// The same for one view only (`view` in [0, shape.views)): a one-view shape.
FrameShape crop_shape(const FrameShape& shape, const Rect& region, int view);
// `shape` with x and y exchanged (width ↔ height, weights transposed per view).
FrameShape transposed(const FrameShape& shape);

// Which part of a frame a RegionBalancer plans.
struct Region {
  Rect rect;
  int view = -1;            // -1: the rect in every view; else only this view
  bool transposed = false;  // the inner balancer splits along the other axis (its rows
                            // become columns): Harada's second level
};

class RegionBalancer : public Balancer {
 public:
  RegionBalancer(std::unique_ptr<Balancer> inner, Region region);
  RegionBalancer(std::unique_ptr<Balancer> inner, Rect rect)
      : RegionBalancer(std::move(inner), Region{rect}) {}

  // The region of the following plans (e.g. a new band from the level above).
  void set_region(const Region& region) { region_ = region; }
  void set_region(const Rect& rect) { region_.rect = rect; }
  const Region& region() const { return region_; }

  std::string name() const override { return inner_->name(); }
  std::string spec() const override { return inner_->spec(); }
  // Items cover the region (clipped to the shape) of every view it names, exactly once.
  // Throws std::invalid_argument for a view outside the shape.
  Plan plan(const FrameShape& shape, int frame) override;
  // Items outside the last planned region are ignored.
  void update(const FrameStats& stats) override;
  void drop_device(int index) override { inner_->drop_device(index); }
  // The inner balancer's axis as it cuts the frame, i.e. swapped when transposed.
  CutAxis cut_axis() const override;

 private:
  FrameShape inner_shape(const FrameShape& shape) const;

  std::unique_ptr<Balancer> inner_;
  Region region_;
  Region planned_;  // the clipped region of the last plan
};

}  // namespace multiray::balance
