#include "render/foveated.h"

#include <algorithm>
#include <array>

namespace multiray {

FoveatedKernel::FoveatedKernel(const PathTracer& tracer, const AmbientOcclusion& ao)
    : tracer_(tracer), ao_(ao) {}

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
    stats += settings.integrator == Integrator::AO
                 ? ao_.render_samples(view, settings, samples.data(), m, result.data())
                 : tracer_.render_samples(view, settings, samples.data(), m, result.data());
    for (size_t i = 0; i < m; ++i) values[idx[first + i]] = result[i];
  }
  return stats;
}

KernelStats FoveatedKernel::render_rect(const ViewSetup& view, const RenderSettings& settings,
                                        PixelRect rect, Framebuffer& out,
                                        std::vector<Vec3>& scratch) const {
  const FoveationFrame& f = *view.foveation;
  if (scratch.size() < f.size()) scratch.resize(f.size());
  const std::vector<uint32_t> idx = select_samples(f, rect);
  const KernelStats stats = shade(view, settings, idx.data(), idx.size(), scratch.data());
  reconstruct_rect(f, scratch.data(), rect, out);
  return stats;
}

void reconstruct_rect(const FoveationFrame& f, const Vec3* values, PixelRect rect,
                      Framebuffer& out) {
  constexpr float kCoincident = 1e-12f;  // squared pixels: closer than 1e-6 px wins
  const int k = f.k;
  std::array<float, 32> weight;  // k <= 32 (check_foveation_params)
  for (int y = rect.y0; y < rect.y1; ++y)
    for (int x = rect.x0; x < rect.x1; ++x) {
      const float cx = float(x) + 0.5f, cy = float(y) + 0.5f;
      const uint32_t* nb = f.neighbours_of(x, y);
      int n = 0, winner = -1;
      for (; n < k && nb[n] != FoveationFrame::kNoSample; ++n) {
        const float d2 = distance2_to_box(f.position[nb[n]], cx, cy, cx, cy);
        if (d2 <= kCoincident && winner < 0) winner = n;
        weight[size_t(n)] = 1.0f / d2;
      }
      if (winner >= 0) {
        out.at(x, y) = values[nb[winner]];
        continue;
      }
      const Vec3 v0 = values[nb[0]];
      float total = weight[0];
      Vec3 acc(0.0f);
      for (int j = 1; j < n; ++j) {
        total += weight[size_t(j)];
        acc += (values[nb[j]] - v0) * weight[size_t(j)];
      }
      out.at(x, y) = v0 + acc / total;
    }
}

}  // namespace multiray
