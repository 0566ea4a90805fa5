#include "render/compact_quantize.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace multiray {

namespace {

// The grid of `divisions` cells along the longest side of `box` (cells as PositionGrid):
// the cell rounded up to 8 significant bits and the origin down to a multiple of the
// cell's last bit, so that corners origin + cell * c are exact floats (8 + 16 bits) and
// the decoder's only rounding is at the vertex's own magnitude.
PositionGrid lattice(const Bounds3& box, uint32_t divisions) {
  PositionGrid g;
  g.origin = box.lo;
  const Vec3 e = box.extent();
  const double longest = std::max({e.x, e.y, e.z});
  if (!(longest > 0)) return g;  // a single point: one cell, offsets zero
  int exponent = 0;
  const double mantissa = std::frexp(longest / divisions, &exponent);  // in [0.5, 1)
  const double cell = std::ldexp(std::ceil(mantissa * 256.0) / 256.0, exponent);
  const double last_bit = std::ldexp(1.0, exponent - 8);
  g.cell = float(cell);
  g.step = g.cell / float(kOffsetLevels);
  for (int a = 0; a < 3; ++a) {
    float o = float(std::floor(double(box.lo[a]) / last_bit) * last_bit);
    while (o > box.lo[a]) o = std::nextafter(o, -INFINITY);
    g.origin[a] = o;
    const double cells = std::ceil((double(box.hi[a]) - double(o)) / cell);
    g.n[a] = uint32_t(std::clamp(cells, 1.0, double(kMaxCellsPerAxis)));
  }
  return g;
}

// The cell of `p` as a key z << 32 | y << 16 | x (the table's order); points outside the
// grid go to its boundary cells. The count and the encoder both use this, so every
// encoded point finds its cell listed.
uint64_t cell_key(const PositionGrid& g, Vec3 p) {
  uint64_t key = 0;
  for (int a = 0; a < 3; ++a) {
    const double f = (double(p[a]) - double(g.origin[a])) / double(g.cell);
    const uint32_t c = std::min(uint32_t(std::clamp(std::floor(f), 0.0, 1e9)), g.n[a] - 1);
    key |= uint64_t(c) << (16 * a);
  }
  return key;
}

uint64_t table_key(const PositionGrid& g, size_t i) {
  return uint64_t(g.cells[3 * i]) | uint64_t(g.cells[3 * i + 1]) << 16 |
         uint64_t(g.cells[3 * i + 2]) << 32;
}

Bounds3 box_of(const std::vector<Vec3>& points) {
  Bounds3 b;
  for (const Vec3& p : points) b.extend(p);
  return b;
}

// Distinct keys, stopping once there are more than `limit`: open addressing in a table of
// at least 4 (limit + 1) slots, so the count stays cheap even for millions of points.
class KeySet {
 public:
  explicit KeySet(uint32_t limit) : limit_(limit) {
    size_t size = 1;
    while (size < 4 * (size_t(limit) + 1)) size *= 2;
    slots_.assign(size, kEmpty);
    mask_ = size - 1;
  }
  // False once the set holds more than `limit` keys.
  bool insert(uint64_t key) {
    size_t i = size_t((key * 0x9E3779B97F4A7C15ull) >> 20) & mask_;
    while (slots_[i] != kEmpty) {
      if (slots_[i] == key) return true;
      i = (i + 1) & mask_;
    }
    slots_[i] = key;
    return ++count_ <= limit_;
  }
  uint32_t count() const { return count_; }
  std::vector<uint64_t> sorted_keys() const {
    std::vector<uint64_t> keys;
    for (uint64_t k : slots_)
      if (k != kEmpty) keys.push_back(k);
    std::sort(keys.begin(), keys.end());
    return keys;
  }

 private:
  static constexpr uint64_t kEmpty = ~uint64_t(0);
  std::vector<uint64_t> slots_;
  size_t mask_ = 0;
  uint32_t limit_, count_ = 0;
};

// Fills `set` with the geometry cells of `points` on `g`; false when they exceed its limit.
bool collect_cells(const PositionGrid& g, const std::vector<Vec3>& points, KeySet& set) {
  for (const Vec3& p : points)
    if (!set.insert(cell_key(g, p))) return false;
  return true;
}

}  // namespace

uint32_t count_geometry_cells(const std::vector<Vec3>& points, uint32_t divisions,
                              uint32_t limit) {
  KeySet set(limit);
  collect_cells(lattice(box_of(points), divisions), points, set);
  return set.count();
}

uint32_t geometry_cell_limit(size_t vertices) {
  return uint32_t(std::clamp<size_t>(vertices / 8, 1, kMaxGridCells));
}

PositionGrid PositionGrid::fit(const std::vector<Vec3>& points, uint32_t max_cells) {
  max_cells = std::clamp<uint32_t>(max_cells, 1, kMaxGridCells);
  if (points.empty()) return PositionGrid{};
  const Bounds3 box = box_of(points);
  // Bisection on the divisions of the longest side: lo fits (one cell always does), hi
  // does not. The count is not monotone in the divisions (the lattice shifts against the
  // geometry), so the result is the finest of the bisection's path, not necessarily the
  // finest of all: lo fits and lo + 1 does not.
  uint32_t lo = 1, hi = kMaxCellsPerAxis - 1;
  if (count_geometry_cells(points, hi, max_cells) <= max_cells) {
    lo = hi;
  } else {
    while (hi - lo > 1) {
      const uint32_t mid = lo + (hi - lo) / 2;
      (count_geometry_cells(points, mid, max_cells) <= max_cells ? lo : hi) = mid;
    }
  }
  PositionGrid g = lattice(box, lo);
  g.divisions = lo;
  KeySet set(kMaxGridCells);
  collect_cells(g, points, set);
  for (uint64_t key : set.sorted_keys())
    for (int a = 0; a < 3; ++a) g.cells.push_back(uint16_t(key >> (16 * a)));
  return g;
}

QuantizedPosition encode_position(const PositionGrid& g, Vec3 p) {
  const uint64_t key = cell_key(g, p);
  size_t first = 0, count = g.cell_count();
  while (count > 0) {  // lower bound of `key` in the sorted table
    const size_t half = count / 2;
    if (table_key(g, first + half) < key) {
      first += half + 1, count -= half + 1;
    } else {
      count = half;
    }
  }
  if (first == g.cell_count() || table_key(g, first) != key)
    throw std::invalid_argument("encode_position: the point's cell is not in the grid's table");
  uint32_t off[3];
  for (int a = 0; a < 3; ++a) {
    // From the corner as the decoder computes it (exact, see lattice()).
    const float corner = g.origin[a] + g.cell * float(uint32_t(key >> (16 * a)) & 0xffffu);
    const double f = (double(p[a]) - double(corner)) / double(g.step);
    off[a] = uint32_t(std::lround(std::clamp(f, 0.0, double(kOffsetLevels))));
  }
  const uint32_t packed = off[0] | off[1] << 10 | off[2] << 20;
  return QuantizedPosition{uint16_t(first), uint16_t(packed & 0xffffu), uint16_t(packed >> 16)};
}

namespace {

// The octahedral map: unit sphere -> [-1, 1]^2 and back.
Vec2 octahedron(Vec3 n) {
  const float s = std::fabs(n.x) + std::fabs(n.y) + std::fabs(n.z);
  float u = n.x / s, v = n.y / s;
  if (n.z < 0) {
    const float fu = (1.0f - std::fabs(v)) * (u >= 0 ? 1.0f : -1.0f);
    const float fv = (1.0f - std::fabs(u)) * (v >= 0 ? 1.0f : -1.0f);
    u = fu, v = fv;
  }
  return Vec2{u, v};
}

}  // namespace

uint16_t encode_normal(Vec3 n) {
  const float len = length(n);
  if (!(len > 0) || !std::isfinite(len)) return encode_normal(Vec3(0, 0, 1));
  n = n * (1.0f / len);
  const Vec2 o = octahedron(n);
  const float fu = std::floor((o.x + 1.0f) * 127.5f), fv = std::floor((o.y + 1.0f) * 127.5f);
  uint16_t best = 0;
  float best_cos = -2.0f;
  for (int du = 0; du < 2; ++du)
    for (int dv = 0; dv < 2; ++dv) {
      const uint32_t bu = uint32_t(std::clamp(fu + float(du), 0.0f, 255.0f));
      const uint32_t bv = uint32_t(std::clamp(fv + float(dv), 0.0f, 255.0f));
      const uint16_t code = uint16_t(bu | bv << 8);
      const float c = dot(decode_normal(code), n);
      if (c > best_cos) best_cos = c, best = code;
    }
  return best;
}

namespace {

// Packs the triangles' shifts (two per triangle) relative to each component's smallest.
UvShifts pack_shifts(const std::vector<int32_t>& shifts) {
  UvShifts s;
  const size_t triangles = shifts.size() / 2;
  int32_t hi[2] = {0, 0};
  for (int a = 0; a < 2; ++a) {
    if (triangles > 0) s.base[a] = hi[a] = shifts[a];
    for (size_t t = 0; t < triangles; ++t) {
      s.base[a] = std::min(s.base[a], shifts[2 * t + a]);
      hi[a] = std::max(hi[a], shifts[2 * t + a]);
    }
    s.bits[a] = bits_for(uint32_t(hi[a] - s.base[a]));
  }
  std::vector<uint32_t> entries(triangles);
  for (size_t t = 0; t < triangles; ++t)
    entries[t] = uint32_t(shifts[2 * t] - s.base[0]) | uint32_t(shifts[2 * t + 1] - s.base[1])
                                                           << s.bits[0];
  s.packed = PackedUints::pack(entries, s.bits[0] + s.bits[1]);
  return s;
}

}  // namespace

QuantizedUvs quantize_uvs(const std::vector<Vec2>& uvs, const std::vector<uint32_t>& indices) {
  QuantizedUvs q;
  const size_t triangles = indices.size() / 3;
  std::vector<int32_t> shifts(2 * triangles);
  q.codes.assign(2 * uvs.size(), 0);
  for (int a = 0; a < 2; ++a) {
    // Shifts, and the largest offset of a corner from its triangle's shift.
    double widest = 0;
    for (size_t t = 0; t < triangles; ++t) {
      double lo = INFINITY, hi = -INFINITY;
      for (int k = 0; k < 3; ++k) {
        const Vec2 uv = uvs[indices[3 * t + k]];
        const double x = a == 0 ? uv.x : uv.y;
        if (std::isfinite(x)) lo = std::min(lo, x), hi = std::max(hi, x);
      }
      const double shift = std::isfinite(lo) ? std::clamp(std::floor(lo), -32768.0, 32767.0) : 0.0;
      shifts[2 * t + a] = int32_t(shift);
      if (std::isfinite(hi)) widest = std::max(widest, hi - shift);
    }
    // The smallest period whose 16-bit steps hold the widest offset once rounded.
    uint32_t e = 0;
    while (e < 15 && std::floor(widest * std::ldexp(1.0, 16 - int(e)) + 0.5) > 65535.0) ++e;
    q.coding.period_log2[a] = e;
    q.coding.step[a] = std::ldexp(1.0f, int(e) - 16);
    // Codes: the coordinate in steps, rounded (floor(x + 1/2) commutes with the integer
    // shift, so code - shift / step is the rounded offset from any triangle's shift),
    // modulo 2^16.
    const double per_unit = std::ldexp(1.0, 16 - int(e));
    for (size_t v = 0; v < uvs.size(); ++v) {
      const double x = std::clamp(double(a == 0 ? uvs[v].x : uvs[v].y), -32768.0, 65536.0);
      const double steps = std::isfinite(x) ? std::floor(x * per_unit + 0.5) : 0.0;
      q.codes[2 * v + a] = uint16_t(int64_t(steps) & 0xffff);
    }
  }
  q.shifts = pack_shifts(shifts);
  return q;
}

}  // namespace multiray
