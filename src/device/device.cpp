#include "device/device.h"

#include <algorithm>

namespace multiray {

namespace {
bool contains(const std::vector<std::string>& list, const std::string& s) {
  return std::find(list.begin(), list.end(), s) != list.end();
}
std::string joined(const std::vector<std::string>& list) {
  std::string out;
  for (const std::string& s : list) out += (out.empty() ? "" : ", ") + s;
  return out.empty() ? "nothing" : out;
}
}  // namespace

std::string unsupported_job(const DeviceInfo& info, const std::string& kernel,
                            const std::string& sampling) {
  if (!contains(info.caps.kernels, kernel))
    return "device '" + info.spec + "' cannot run the " + kernel + " kernel (it runs " +
           joined(info.caps.kernels) + ")";
  if (!contains(info.caps.sampling, sampling))
    return "device '" + info.spec + "' cannot do " + sampling + " sampling (it does " +
           joined(info.caps.sampling) + ")";
  return "";
}

std::vector<std::string> sampling_modes(bool point_samples) {
  if (point_samples) return {"uniform", "adaptive", "foveated", "reproject"};
  return {"uniform", "adaptive", "reproject"};
}

size_t WorkSource::next(int device, size_t max, std::vector<uint32_t>& ids) {
  size_t n = 0;
  for (uint32_t id; n < max && next(device, id); ++n) ids.push_back(id);
  return n;
}

void DeviceReport::add(const ItemReport& r, uint64_t rays_of_item) {
  items.push_back(r);
  busy_ms += r.busy_ms;
  samples += uint64_t(r.samples);
  rays += rays_of_item;
  pixels += uint64_t(r.item.rect.area());
}

}  // namespace multiray
