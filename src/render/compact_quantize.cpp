#include "render/compact_quantize.h"

#include <algorithm>
#include <cmath>

namespace multiray {

namespace {

// Cells needed along an axis of length `e` at cell size `c` (at least one).
double cells_along(double e, double c) { return std::max(1.0, std::ceil(e / c)); }

double cells_for(const double e[3], double c) {
  return cells_along(e[0], c) * cells_along(e[1], c) * cells_along(e[2], c);
}

}  // namespace

PositionGrid PositionGrid::fit(const Bounds3& box) {
  PositionGrid g;
  if (box.empty()) return g;
  g.origin = box.lo;
  const Vec3 ext = box.extent();
  const double e[3] = {ext.x, ext.y, ext.z};
  const double longest = std::max({e[0], e[1], e[2]});
  if (!(longest > 0)) return g;  // every vertex at one point: one cell, offsets zero
  // cells_for() falls as the cell grows; at `longest` one cell per axis suffices. Bisect
  // for the smallest feasible size, then round it up to a float that stays feasible.
  double lo = 0, hi = longest;
  for (int i = 0; i < 64; ++i) {
    const double mid = 0.5 * (lo + hi);
    (cells_for(e, mid) <= kMaxGridCells ? hi : lo) = mid;
  }
  float cell = float(hi);
  while (cells_for(e, cell) > kMaxGridCells) cell = std::nextafter(cell, INFINITY);
  g.cell = cell;
  for (int a = 0; a < 3; ++a) g.n[a] = uint32_t(cells_along(e[a], cell));
  g.magic_n0 = division_magic(g.n[0]);
  g.magic_n01 = division_magic(g.n[0] * g.n[1]);
  return g;
}

QuantizedPosition encode_position(const PositionGrid& g, Vec3 p) {
  const float v[3] = {p.x - g.origin.x, p.y - g.origin.y, p.z - g.origin.z};
  uint32_t cell[3], off[3];
  for (int a = 0; a < 3; ++a) {
    const double f = std::max(0.0, double(v[a]) / double(g.cell));
    cell[a] = std::min(uint32_t(std::min(f, 1e9)), g.n[a] - 1);
    const double frac = std::clamp(f - double(cell[a]), 0.0, 1.0);
    off[a] = uint32_t(std::lround(frac * kOffsetLevels));
  }
  const uint32_t index = cell[0] + g.n[0] * (cell[1] + g.n[1] * cell[2]);
  const uint32_t packed = off[0] | off[1] << 10 | off[2] << 20;
  return QuantizedPosition{uint16_t(index), uint16_t(packed & 0xffffu), uint16_t(packed >> 16)};
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

float from_byte(uint32_t b) { return float(b) * (2.0f / 255.0f) - 1.0f; }

}  // namespace

Vec3 decode_normal(uint16_t code) {
  const float u = from_byte(code & 0xffu), v = from_byte(code >> 8);
  Vec3 n(u, v, 1.0f - std::fabs(u) - std::fabs(v));
  if (n.z < 0) {
    const float x = (1.0f - std::fabs(v)) * (u >= 0 ? 1.0f : -1.0f);
    const float y = (1.0f - std::fabs(u)) * (v >= 0 ? 1.0f : -1.0f);
    n.x = x, n.y = y;
  }
  return normalize(n);
}

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

UvRange UvRange::fit(Vec2 lo, Vec2 hi) {
  UvRange r;
  if (!(lo.x <= hi.x && lo.y <= hi.y)) return r;
  r.lo = lo;
  r.scale = Vec2{(hi.x - lo.x) / 65535.0f, (hi.y - lo.y) / 65535.0f};
  return r;
}

void encode_uv(const UvRange& r, Vec2 uv, uint16_t out[2]) {
  const float in[2] = {uv.x - r.lo.x, uv.y - r.lo.y};
  const float scale[2] = {r.scale.x, r.scale.y};
  for (int a = 0; a < 2; ++a) {
    const double q = scale[a] > 0 ? double(in[a]) / double(scale[a]) : 0.0;
    out[a] = !(q > 0) ? 0 : uint16_t(std::lround(std::min(q, 65535.0)));  // NaN -> 0
  }
}

}  // namespace multiray
