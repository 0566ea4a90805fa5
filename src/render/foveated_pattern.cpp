#include "render/foveated_pattern.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "render/rng.h"

namespace multiray {

std::string check_foveation_params(const FoveationParams& p) {
  if (!(p.fovea_spp > 0 && p.fovea_spp <= 64)) return "fovea samples per pixel must be in (0, 64]";
  if (!(p.fovea_radius > 0 && std::isfinite(p.fovea_radius)))
    return "fovea radius must be a finite fraction of the image height > 0";
  if (!(p.periphery_spp >= 1.0f / 4096 && p.periphery_spp <= p.fovea_spp))
    return "periphery samples per pixel must be in [1/4096, fovea samples per pixel]";
  if (p.neighbours < 1 || p.neighbours > 32) return "neighbours (k) must be in 1..32";
  return {};
}

float foveation_density(const FoveationParams& p, float r_px, float r0_px) {
  const float q = r_px / r0_px;
  return std::max(p.periphery_spp, p.fovea_spp / (1.0f + q * q));
}

FoveationPattern make_foveation_pattern(int width, int height, const FoveationParams& p) {
  if (width < 1 || height < 1) throw InputError("foveated sampling: the image is empty");
  if (const std::string why = check_foveation_params(p); !why.empty())
    throw InputError("foveated sampling: " + why);
  FoveationPattern pat;
  pat.width = width, pat.height = height, pat.params = p;
  pat.offsets.push_back(Vec2{0.0f, 0.0f});

  const float r0 = p.fovea_radius * float(height);
  // B x B cells per block: about one sample per block where the density is at its floor.
  const int b = std::clamp(int(std::lround(1.0 / std::sqrt(double(p.periphery_spp)))), 1, 64);
  // Blocks cover [-width, width) x [-height, height); block (0, 0) starts at the gaze.
  const int bx0 = -((width + b - 1) / b), bx1 = (width + b - 1) / b;
  const int by0 = -((height + b - 1) / b), by1 = (height + b - 1) / b;
  std::vector<double> cdf(size_t(b) * size_t(b));
  for (int by = by0; by < by1; ++by)
    for (int bx = bx0; bx < bx1; ++bx) {
      // Cell (i, j) of the block spans offsets [x, x+1) x [y, y+1), x = bx·B + i.
      double total = 0;
      for (int j = 0; j < b; ++j)
        for (int i = 0; i < b; ++i) {
          const float cx = float(bx * b + i) + 0.5f, cy = float(by * b + j) + 0.5f;
          total += foveation_density(p, std::sqrt(cx * cx + cy * cy), r0);
          cdf[size_t(j * b + i)] = total;
        }
      // One random stream per block, keyed by the block: the pattern does not depend on
      // the order blocks are visited in.
      const uint64_t key = uint64_t(uint32_t(bx)) << 32 | uint32_t(by);
      Rng rng(mix64(key ^ p.seed), p.seed);
      const int n = int(total) + (double(rng.next()) < total - std::floor(total) ? 1 : 0);
      for (int s = 0; s < n; ++s) {
        // Stratified choice: sample s takes the cell where the CDF crosses (s + u) / n.
        const double target = (double(s) + double(rng.next())) / double(n) * total;
        const size_t cell = size_t(std::upper_bound(cdf.begin(), cdf.end(), target) - cdf.begin());
        const int i = int(std::min(cell, cdf.size() - 1)) % b;
        const int j = int(std::min(cell, cdf.size() - 1)) / b;
        const float jx = rng.next(), jy = rng.next();
        pat.offsets.push_back(Vec2{float(bx * b + i) + jx, float(by * b + j) + jy});
      }
    }
  return pat;
}

}  // namespace multiray
