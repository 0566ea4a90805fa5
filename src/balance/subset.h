// `subset` (ours, a baseline): the frame rendered by some of the devices only, the others
// left out (Plan::resting: not started at all), split among those by hybrid with one band
// and without its participation rule (`hybrid:bands=1:leave=0`, the default before issue
// 50). `subset:devices=1` is device 1 alone; `subset:devices=0+2` devices 0 and 2. It is
// what the regret table of `multiray bench --regret` compares the default against: each
// device alone and every other subset, on the same frames. When every member has been
// dropped (failed), the devices still alive take over, so the frame is still rendered.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "balance/balancer.h"

namespace multiray::balance {

class SubsetBalancer final : public Balancer {
 public:
  // `members`: the devices that render, distinct indices in 0..device_count-1, at least
  // one (std::invalid_argument otherwise).
  SubsetBalancer(int device_count, std::vector<int> members);

  std::string name() const override { return "subset"; }
  std::string spec() const override;
  Plan plan(const FrameShape& shape, int frame) override;
  void update(const FrameStats& stats) override;
  void drop_device(int index) override;
  CutAxis cut_axis() const override { return inner_->cut_axis(); }

  // "0+2" -> {0, 2}; std::invalid_argument for anything else.
  static std::vector<int> parse_members(const std::string& text, int device_count);

 private:
  // A hybrid over `members_` (dropped ones dropped in it too).
  void build_inner();

  int device_count_;
  std::vector<int> members_;  // inner device k is device members_[k]
  std::vector<bool> alive_;   // per device
  std::unique_ptr<Balancer> inner_;
};

}  // namespace multiray::balance
