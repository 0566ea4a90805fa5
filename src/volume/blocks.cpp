#include "volume/blocks.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace multiray {

namespace {

// Voxel box [lo, hi) of one block along the three axes.
struct Box {
  int lo[3], hi[3];
};

Box own_box(const Volume& v, int bx, int by, int bz) {
  const int b[3] = {bx, by, bz}, n[3] = {v.nx, v.ny, v.nz};
  Box box;
  for (int a = 0; a < 3; ++a) {
    box.lo[a] = block_begin(b[a]);
    box.hi[a] = box.lo[a] + block_length(b[a], n[a]);
  }
  return box;
}

Box with_apron(const Volume& v, Box box) {
  const int n[3] = {v.nx, v.ny, v.nz};
  for (int a = 0; a < 3; ++a) {
    box.lo[a] = std::max(box.lo[a] - 1, 0);
    box.hi[a] = std::min(box.hi[a] + 1, n[a]);
  }
  return box;
}

// Density bins per unit value: kDensityBins over [min_value, max_value]; 0 when constant.
double bins_per_value(const Volume& v) {
  const double span = double(v.max_value) - double(v.min_value);
  return span > 0 ? kDensityBins / span : 0.0;
}

// Extends four running ranges lo[k], hi[k] by the n values at p (k = index mod 4), so
// the four comparisons of each step do not wait for one another.
void extend_range(const float* p, int n, float lo[4], float hi[4]) {
  float l0 = lo[0], l1 = lo[1], l2 = lo[2], l3 = lo[3];
  float h0 = hi[0], h1 = hi[1], h2 = hi[2], h3 = hi[3];
  int i = 0;
  for (; i + 4 <= n; i += 4) {
    l0 = std::min(l0, p[i]), h0 = std::max(h0, p[i]);
    l1 = std::min(l1, p[i + 1]), h1 = std::max(h1, p[i + 1]);
    l2 = std::min(l2, p[i + 2]), h2 = std::max(h2, p[i + 2]);
    l3 = std::min(l3, p[i + 3]), h3 = std::max(h3, p[i + 3]);
  }
  for (; i < n; ++i) l0 = std::min(l0, p[i]), h0 = std::max(h0, p[i]);
  lo[0] = l0, lo[1] = l1, lo[2] = l2, lo[3] = l3;
  hi[0] = h0, hi[1] = h1, hi[2] = h2, hi[3] = h3;
}

// One pass over the block and its apron, row by row: the range over every row of the
// apron box, the histogram over the block's own part of its own rows.
void build_block(const Volume& v, VolumeBlocks* out, int bx, int by, int bz) {
  const size_t i = out->index(bx, by, bz);
  const Box own = own_box(v, bx, by, bz);
  const Box apron = with_apron(v, own);
  const float base = v.min_value;
  const float scale = float(bins_per_value(v));
  // Four running minima, maxima and histograms break the dependency chains (a block is
  // often one value: every increment would wait for the previous one).
  float lo[4] = {INFINITY, INFINITY, INFINITY, INFINITY};
  float hi[4] = {-INFINITY, -INFINITY, -INFINITY, -INFINITY};
  uint32_t h[4][kDensityBins] = {};
  for (int z = apron.lo[2]; z < apron.hi[2]; ++z) {
    for (int y = apron.lo[1]; y < apron.hi[1]; ++y) {
      const float* row = &v.values[(size_t(z) * size_t(v.ny) + size_t(y)) * size_t(v.nx)];
      extend_range(row + apron.lo[0], apron.hi[0] - apron.lo[0], lo, hi);
      if (z < own.lo[2] || z >= own.hi[2] || y < own.lo[1] || y >= own.hi[1]) continue;
      for (int x = own.lo[0]; x < own.hi[0]; ++x) {
        const int b = int((row[x] - base) * scale);
        ++h[x & 3][b < 0 ? 0 : (b >= kDensityBins ? kDensityBins - 1 : b)];
      }
    }
  }
  std::array<uint32_t, kDensityBins>& d = out->density[i];
  for (int b = 0; b < kDensityBins; ++b) d[size_t(b)] = h[0][b] + h[1][b] + h[2][b] + h[3][b];
  out->min_value[i] = std::min(std::min(lo[0], lo[1]), std::min(lo[2], lo[3]));
  out->max_value[i] = std::max(std::max(hi[0], hi[1]), std::max(hi[2], hi[3]));
}

}  // namespace

VolumeBlocks build_blocks(const Volume& volume) {
  VolumeBlocks b;
  b.bx = (volume.nx + kBlockSize - 1) / kBlockSize;
  b.by = (volume.ny + kBlockSize - 1) / kBlockSize;
  b.bz = (volume.nz + kBlockSize - 1) / kBlockSize;
  b.min_value.assign(b.count(), 0);
  b.max_value.assign(b.count(), 0);
  b.density.resize(b.count());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, b.count()), [&](const auto& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const int x = int(i % size_t(b.bx));
      const int y = int(i / size_t(b.bx) % size_t(b.by));
      const int z = int(i / (size_t(b.bx) * size_t(b.by)));
      build_block(volume, &b, x, y, z);
    }
  });
  return b;
}

std::array<float, 2> density_bin_range(const Volume& volume, int bin) {
  const double scale = bins_per_value(volume);
  if (scale == 0) return {volume.min_value, volume.min_value};
  const double lo = volume.min_value + bin / scale;
  const double hi =
      bin + 1 == kDensityBins ? volume.max_value : volume.min_value + (bin + 1) / scale;
  return {float(lo), float(hi)};
}

BlockOpacity block_opacity(const VolumeBlocks& blocks, const TransferFunction& tf,
                           const Volume& volume) {
  if (tf.units != TfUnits::data || tf.points.size() < 2)
    throw std::invalid_argument("block_opacity needs a resolved transfer function");
  // Opacity bound of each whole density bin, shared by every block.
  std::array<std::array<float, 2>, kDensityBins> range;
  std::array<float, kDensityBins> bin_max;
  for (int b = 0; b < kDensityBins; ++b) {
    range[size_t(b)] = density_bin_range(volume, b);
    bin_max[size_t(b)] = max_opacity(tf, range[size_t(b)][0], range[size_t(b)][1]);
  }
  BlockOpacity out;
  out.histogram.resize(blocks.count());
  out.max_opacity.resize(blocks.count());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, blocks.count()), [&](const auto& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const float lo = blocks.min_value[i], hi = blocks.max_value[i];
      out.max_opacity[i] = max_opacity(tf, lo, hi);
      std::array<float, kOpacityBins>& h = out.histogram[i];
      h.fill(0);
      uint64_t voxels = 0;
      for (size_t b = 0; b < size_t(kDensityBins); ++b) {
        const uint32_t c = blocks.density[i][b];
        if (c == 0) continue;
        voxels += c;
        // Bins cut by the block's range are bounded over the part inside it.
        const bool whole = range[b][0] >= lo && range[b][1] <= hi;
        const float a0 = std::min(std::max(range[b][0], lo), hi);
        const float a1 = std::max(std::min(range[b][1], hi), a0);
        const float a = whole ? bin_max[b] : max_opacity(tf, a0, a1);
        h[size_t(std::clamp(int(a * kOpacityBins), 0, kOpacityBins - 1))] += float(c);
      }
      if (voxels > 0)
        for (float& f : h) f /= float(voxels);
    }
  });
  return out;
}

}  // namespace multiray
