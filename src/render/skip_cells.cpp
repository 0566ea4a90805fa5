#include "render/skip_cells.h"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

namespace multiray {

SkipCells build_skip_cells(const Volume& v) {
  SkipCells c;
  c.cx = (v.nx + kSkipCell - 1) / kSkipCell;
  c.cy = (v.ny + kSkipCell - 1) / kSkipCell;
  c.cz = (v.nz + kSkipCell - 1) / kSkipCell;
  c.min_value.assign(c.count(), INFINITY);
  c.max_value.assign(c.count(), -INFINITY);
  // Each cell z-slab is one task: it writes only its own cells.
  tbb::parallel_for(0, c.cz, [&](int kz) {
    for (int ky = 0; ky < c.cy; ++ky)
      for (int kx = 0; kx < c.cx; ++kx) {
        // The cell's voxels and a one-voxel apron, clipped to the grid.
        const int x0 = std::max(kx * kSkipCell - 1, 0),
                  x1 = std::min((kx + 1) * kSkipCell + 1, v.nx);
        const int y0 = std::max(ky * kSkipCell - 1, 0),
                  y1 = std::min((ky + 1) * kSkipCell + 1, v.ny);
        const int z0 = std::max(kz * kSkipCell - 1, 0),
                  z1 = std::min((kz + 1) * kSkipCell + 1, v.nz);
        float lo = INFINITY, hi = -INFINITY;
        for (int z = z0; z < z1; ++z)
          for (int y = y0; y < y1; ++y) {
            const float* row = &v.values[(size_t(z) * size_t(v.ny) + size_t(y)) * size_t(v.nx)];
            for (int x = x0; x < x1; ++x) lo = std::min(lo, row[x]), hi = std::max(hi, row[x]);
          }
        const size_t i = (size_t(kz) * size_t(c.cy) + size_t(ky)) * size_t(c.cx) + size_t(kx);
        c.min_value[i] = lo, c.max_value[i] = hi;
      }
  });
  return c;
}

std::vector<float> cell_max_opacity(const SkipCells& c, const TransferTable& table) {
  const int n = int(table.rgba.size()), last = n - 1;
  // levels[k][i]: the largest alpha of entries [i, i + 2^k).
  std::vector<std::vector<float>> levels(1, std::vector<float>(size_t(n)));
  for (int i = 0; i < n; ++i) levels[0][size_t(i)] = table.rgba[size_t(i)][3];
  for (int k = 1; (1 << k) <= n; ++k) {
    const std::vector<float>& prev = levels.back();
    std::vector<float> next(size_t(n - (1 << k) + 1));
    for (size_t i = 0; i < next.size(); ++i)
      next[i] = std::max(prev[i], prev[i + (size_t(1) << (k - 1))]);
    levels.push_back(std::move(next));
  }
  const float to_index = float(last) / std::max(table.hi - table.lo, 1e-30f);
  auto index = [&](float v) { return std::clamp((v - table.lo) * to_index, 0.0f, float(last)); };
  std::vector<float> out(c.count());
  for (size_t i = 0; i < out.size(); ++i) {
    const int lo = std::max(int(std::floor(index(c.min_value[i]))) - 1, 0);
    const int hi = std::min(int(std::ceil(index(c.max_value[i]))) + 1, last);
    int k = 0;
    while ((2 << k) <= hi - lo + 1) ++k;
    out[i] = std::max(levels[size_t(k)][size_t(lo)], levels[size_t(k)][size_t(hi - (1 << k) + 1)]);
  }
  return out;
}

}  // namespace multiray
