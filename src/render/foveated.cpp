#include "render/foveated.h"

#include <algorithm>
#include <array>
#include <stdexcept>
#include <string>

namespace multiray {

const FoveationFrame& foveation_of(const ViewSetup& view) {
  if (!view.foveation) throw std::invalid_argument("foveated rendering of a view without samples");
  const FoveationFrame& f = *view.foveation;
  if (f.width != view.width || f.height != view.height)
    throw std::invalid_argument("foveation data of " + std::to_string(f.width) + "x" +
                                std::to_string(f.height) + " for a view of " +
                                std::to_string(view.width) + "x" + std::to_string(view.height));
  return f;
}

KernelStats FoveatedKernel::shade(const ViewSetup& view, const RenderSettings& settings,
                                  const uint32_t* idx, size_t n, Vec3* values) const {
  const FoveationFrame& f = *view.foveation;
  KernelStats stats;
  // Chunks as large as the path tracer's wavefront batch.
  constexpr size_t kChunk = 64;
  std::array<ImageSample, kChunk> samples;
  std::array<Vec3, kChunk> result;
  for (size_t first = 0; first < n; first += kChunk) {
    const size_t m = std::min(kChunk, n - first);
    for (size_t i = 0; i < m; ++i) {
      const uint32_t s = idx[first + i];
      samples[i] = ImageSample{f.position[s].x, f.position[s].y, f.id[s]};
    }
    stats += sampled_.render_samples(view, settings, samples.data(), m, result.data());
    for (size_t i = 0; i < m; ++i) values[idx[first + i]] = result[i];
  }
  return stats;
}

KernelStats FoveatedKernel::render_rect(const ViewSetup& view, const RenderSettings& settings,
                                        Rect rect, Framebuffer& out,
                                        std::vector<Vec3>& scratch) const {
  const FoveationFrame& f = foveation_of(view);
  if (scratch.size() < f.size()) scratch.resize(f.size());
  const std::vector<uint32_t> idx = select_samples(f, rect);
  const KernelStats stats = shade(view, settings, idx.data(), idx.size(), scratch.data());
  reconstruct_rect(f, scratch.data(), rect, out);
  return stats;
}

void reconstruct_rect(const FoveationFrame& f, const Vec3* values, Rect rect, Framebuffer& out) {
  for (int y = rect.y0; y < rect.y1; ++y)
    for (int x = rect.x0; x < rect.x1; ++x) {
      const uint32_t* nb = f.neighbours_of(x, y);
      const float* w = f.weights_of(x, y);
      const Vec3 v0 = values[nb[0]];
      Vec3 acc(0.0f);
      for (int j = 1; j < f.k && nb[j] != FoveationFrame::kNoSample; ++j)
        acc += (values[nb[j]] - v0) * w[j];
      out.at(x, y) = v0 + acc;
    }
}

}  // namespace multiray
