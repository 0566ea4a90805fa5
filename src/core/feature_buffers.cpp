#include "core/feature_buffers.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>

#include <xxhash.h>

#include "core/error.h"
#include "util/nearest.h"

namespace multiray {

void FeatureBuffers::resize(int w, int h) {
  const size_t n = size_t(w) * size_t(h);
  width = w, height = h;
  albedo.resize(3 * n);
  normal.resize(3 * n);
  depth.resize(n);
  variance.resize(n);
  emission.resize(3 * n);
}

void FeatureBuffers::set_packed(size_t i, const float* v) {
  std::copy(v, v + 3, &albedo[3 * i]);
  std::copy(v + 3, v + 6, &normal[3 * i]);
  depth[i] = v[6];
  variance[i] = v[7];
  std::copy(v + 8, v + 11, &emission[3 * i]);
}

void FeatureBuffers::get_packed(size_t i, float* v) const {
  std::copy(&albedo[3 * i], &albedo[3 * i] + 3, v);
  std::copy(&normal[3 * i], &normal[3 * i] + 3, v + 3);
  v[6] = depth[i];
  v[7] = variance[i];
  std::copy(&emission[3 * i], &emission[3 * i] + 3, v + 8);
}

std::vector<float> packed_features(const FeatureBuffers& f, Rect r) {
  std::vector<float> v(size_t(r.area()) * FeatureBuffers::kFloats);
  float* out = v.data();
  for (int y = r.y0; y < r.y1; ++y)
    for (int x = r.x0; x < r.x1; ++x, out += FeatureBuffers::kFloats)
      f.get_packed(size_t(y) * size_t(f.width) + size_t(x), out);
  return v;
}

void unpack_features(const std::vector<float>& v, Rect r, FeatureBuffers& f) {
  if (v.size() != size_t(r.area()) * FeatureBuffers::kFloats || r.x1 > f.width || r.y1 > f.height)
    throw std::invalid_argument("feature buffers: values do not match the rect");
  const float* in = v.data();
  for (int y = r.y0; y < r.y1; ++y)
    for (int x = r.x0; x < r.x1; ++x, in += FeatureBuffers::kFloats)
      f.set_packed(size_t(y) * size_t(f.width) + size_t(x), in);
}

uint64_t feature_hash(const FeatureBuffers& f, uint64_t seed) {
  uint64_t h = seed;
  for (const std::vector<float>* buffer :
       {&f.albedo, &f.normal, &f.depth, &f.variance, &f.emission})
    h = XXH3_64bits_withSeed(buffer->data(), buffer->size() * sizeof(float), h);
  return h;
}

const std::vector<std::string>& aov_names() {
  static const std::vector<std::string> names{"albedo", "normal", "depth", "variance", "emission"};
  return names;
}

std::vector<std::string> check_aov_names(const std::vector<std::string>& names,
                                         const std::string& option) {
  if (names.empty())
    throw InputError(option + " needs at least one of albedo, normal, depth, variance, emission");
  for (const std::string& n : names) {
    if (std::find(aov_names().begin(), aov_names().end(), n) != aov_names().end()) continue;
    const std::string best = nearest_name(n, aov_names());
    throw InputError(option + ": unknown AOV '" + n + "'" +
                     (best.empty() ? "" : " (did you mean " + best + "?)") +
                     "; known: albedo, normal, depth, variance, emission");
  }
  std::vector<std::string> out;
  for (const std::string& known : aov_names())
    if (std::find(names.begin(), names.end(), known) != names.end()) out.push_back(known);
  return out;
}

std::vector<std::string> parse_aov_list(const std::string& list, const std::string& option) {
  std::vector<std::string> names;
  size_t start = 0;
  while (start <= list.size()) {
    const size_t comma = std::min(list.find(',', start), list.size());
    const std::string name = list.substr(start, comma - start);
    if (!name.empty()) names.push_back(name);
    start = comma + 1;
  }
  return check_aov_names(names, option);
}

}  // namespace multiray
