#include "balance/subset.h"

#include <algorithm>
#include <stdexcept>

#include "balance/hybrid.h"

namespace multiray::balance {

std::vector<int> SubsetBalancer::parse_members(const std::string& text, int device_count) {
  std::vector<int> out;
  size_t at = 0;
  while (at <= text.size()) {
    const size_t plus = std::min(text.find('+', at), text.size());
    const std::string part = text.substr(at, plus - at);
    if (part.empty() || part.size() > 4 ||
        part.find_first_not_of("0123456789") != std::string::npos)
      throw std::invalid_argument("subset: devices '" + text +
                                  "' is not a list of device indices such as 0+2");
    const int d = std::stoi(part);
    if (d >= device_count)
      throw std::invalid_argument("subset: device " + part + " of " +
                                  std::to_string(device_count) + " (numbered from 0)");
    if (std::find(out.begin(), out.end(), d) != out.end())
      throw std::invalid_argument("subset: device " + part + " named twice");
    out.push_back(d);
    at = plus + 1;
  }
  return out;
}

SubsetBalancer::SubsetBalancer(int device_count, std::vector<int> members)
    : device_count_(device_count),
      members_(std::move(members)),
      alive_(size_t(std::max(device_count, 0)), true) {
  if (members_.empty()) throw std::invalid_argument("subset: no device");
  for (int d : members_)
    if (d < 0 || d >= device_count) throw std::invalid_argument("subset: device out of range");
  build_inner();
}

void SubsetBalancer::build_inner() {
  HybridBalancer::Options o;
  o.bands = 1;
  o.leave = false;
  inner_ = std::make_unique<HybridBalancer>(int(members_.size()), o);
  for (size_t k = 0; k < members_.size(); ++k)
    if (!alive_[size_t(members_[k])]) inner_->drop_device(int(k));
}

std::string SubsetBalancer::spec() const {
  std::string list;
  for (int d : members_) {
    if (!list.empty()) list += '+';
    list += std::to_string(d);
  }
  return "subset:devices=" + list;
}

Plan SubsetBalancer::plan(const FrameShape& shape, int frame) {
  Plan in = inner_->plan(shape, frame);
  Plan out = in;
  const size_t n = size_t(device_count_);
  out.assigned.assign(n, {});
  out.ratios.assign(n, 0.0);
  out.resting.assign(n, true);
  out.rest_reason.assign(n, "not in the subset");
  out.no_steal.clear();
  out.models.clear();
  for (size_t k = 0; k < members_.size(); ++k) {
    const size_t d = size_t(members_[k]);
    out.assigned[d] = std::move(in.assigned[k]);
    out.ratios[d] = in.ratios[k];
    out.resting[d] = false;
    out.rest_reason[d].clear();
  }
  return out;
}

void SubsetBalancer::update(const FrameStats& stats) {
  for (size_t d = 0; d < stats.devices.size() && d < alive_.size(); ++d)
    if (!stats.devices[d].alive && alive_[d]) drop_device(int(d));
  FrameStats in;
  in.frame = stats.frame;
  in.shape = stats.shape;
  for (int d : members_)
    in.devices.push_back(size_t(d) < stats.devices.size() ? stats.devices[size_t(d)]
                                                          : DeviceFrameStats{});
  inner_->update(in);
}

void SubsetBalancer::drop_device(int index) {
  if (index < 0 || index >= device_count_ || !alive_[size_t(index)]) return;
  alive_[size_t(index)] = false;
  const auto it = std::find(members_.begin(), members_.end(), index);
  if (it != members_.end()) inner_->drop_device(int(it - members_.begin()));
  bool member_left = false;
  for (int d : members_) member_left |= alive_[size_t(d)];
  if (member_left) return;
  // Every member failed: the devices still alive take over (none: an empty plan).
  std::vector<int> rest;
  for (int d = 0; d < device_count_; ++d)
    if (alive_[size_t(d)]) rest.push_back(d);
  if (rest.empty()) return;
  members_ = std::move(rest);
  build_inner();
}

}  // namespace multiray::balance
