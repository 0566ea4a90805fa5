// Balancing a part of a frame: one level of a hierarchy. Harada's distributed split
// (GPU Pro 7, Fig. 4.5) gives each machine a band of the frame and lets each machine
// split its band across its own GPUs; an MPI rank with several local devices does the
// same with the region the master gave it. RegionBalancer lets any balancer do that: it
// plans the region as if it were a whole frame (a frame of the region's size, weights
// cropped) and moves the items into place; measurements are moved back before the inner
// balancer learns from them. Items of every view are cut to the same region.
#pragma once

#include <memory>
#include <string>

#include "balance/balancer.h"

namespace multiray::balance {

// `shape` cut to `region` (clipped to the frame): the region's size, the same views, the
// weights of the region's pixels. Throws std::invalid_argument for an empty region.
FrameShape crop_shape(const FrameShape& shape, const Rect& region);

class RegionBalancer : public Balancer {
 public:
  RegionBalancer(std::unique_ptr<Balancer> inner, Rect region);

  // The region of the following plans (e.g. a new band from the level above).
  void set_region(const Rect& region) { region_ = region; }
  const Rect& region() const { return region_; }

  std::string name() const override { return inner_->name(); }
  std::string spec() const override { return inner_->spec(); }
  // Items cover the region (clipped to the shape) of every view, exactly once.
  Plan plan(const FrameShape& shape, int frame) override;
  // Items outside the last planned region are ignored.
  void update(const FrameStats& stats) override;
  void drop_device(int index) override { inner_->drop_device(index); }

 private:
  std::unique_ptr<Balancer> inner_;
  Rect region_;
  Rect planned_;  // the clipped region of the last plan
};

}  // namespace multiray::balance
