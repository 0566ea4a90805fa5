#include "scene/mitsuba_spectrum.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>

namespace multiray::detail {
namespace {

// The fit's lobe: a Gaussian with a different width on each side of its peak.
double lobe(double x, double mean, double sigma_below, double sigma_above) {
  const double t = (x - mean) / (x < mean ? sigma_below : sigma_above);
  return std::exp(-0.5 * t * t);
}

// The range the CIE tables cover; spectra are integrated over its overlap with theirs.
constexpr double kMinNm = 360.0, kMaxNm = 830.0;
constexpr double kStepNm = 0.5;

// Integral of value(nm) * cie1931_xyz(nm) over [lo, hi] (midpoint rule, kStepNm steps).
template <class Value>
Vec3 integrate_xyz(double lo, double hi, Value value) {
  double x = 0, y = 0, z = 0;
  for (double nm = lo + 0.5 * kStepNm; nm < hi; nm += kStepNm) {
    const Vec3 c = cie1931_xyz(nm);
    const double v = value(nm) * kStepNm;
    x += v * c.x, y += v * c.y, z += v * c.z;
  }
  return Vec3(float(x), float(y), float(z));
}

// Linear interpolation of `s` at `nm`, within [s.nm.front(), s.nm.back()].
double interpolate(const SampledSpectrum& s, double nm) {
  const auto it = std::upper_bound(s.nm.begin(), s.nm.end(), nm);
  if (it == s.nm.begin()) return s.value.front();
  if (it == s.nm.end()) return s.value.back();
  const size_t i = size_t(it - s.nm.begin());
  const double t = (nm - s.nm[i - 1]) / (s.nm[i] - s.nm[i - 1]);
  return s.value[i - 1] + t * (s.value[i] - s.value[i - 1]);
}

// XYZ of `s` with Y = 1 for a flat spectrum of 1 over the whole CIE range.
Vec3 normalised_xyz(const SampledSpectrum& s) {
  static const float y_of_flat = integrate_xyz(kMinNm, kMaxNm, [](double) { return 1.0; }).y;
  if (s.nm.empty()) return Vec3(0.0f);
  const double lo = std::max(kMinNm, s.nm.front()), hi = std::min(kMaxNm, s.nm.back());
  if (!(lo < hi)) return Vec3(0.0f);
  return integrate_xyz(lo, hi, [&](double nm) { return interpolate(s, nm); }) / y_of_flat;
}

bool parse_double(const char* first, const char* last, double* out) {
  while (first < last && std::isspace(static_cast<unsigned char>(*first))) ++first;
  while (last > first && std::isspace(static_cast<unsigned char>(last[-1]))) --last;
  const auto [end, ec] = std::from_chars(first, last, *out);
  return ec == std::errc() && end == last && std::isfinite(*out);
}

}  // namespace

Vec3 cie1931_xyz(double nm) {
  const double x = 1.056 * lobe(nm, 599.8, 37.9, 31.0) + 0.362 * lobe(nm, 442.0, 16.0, 26.7) -
                   0.065 * lobe(nm, 501.1, 20.4, 26.2);
  const double y = 0.821 * lobe(nm, 568.8, 46.9, 40.5) + 0.286 * lobe(nm, 530.9, 16.3, 31.1);
  const double z = 1.217 * lobe(nm, 437.0, 11.8, 36.0) + 0.681 * lobe(nm, 459.0, 26.0, 13.8);
  return Vec3(float(x), float(y), float(z));
}

Vec3 xyz_to_linear_srgb(Vec3 c) {
  // IEC 61966-2-1 (sRGB), D65 white.
  return Vec3(3.2404542f * c.x - 1.5371385f * c.y - 0.4985314f * c.z,
              -0.9692660f * c.x + 1.8760108f * c.y + 0.0415560f * c.z,
              0.0556434f * c.x - 0.2040259f * c.y + 1.0572252f * c.z);
}

Vec3 radiance_spectrum_to_rgb(const SampledSpectrum& s) {
  return max(xyz_to_linear_srgb(normalised_xyz(s)), Vec3(0.0f));
}

Vec3 reflectance_spectrum_to_rgb(const SampledSpectrum& s) {
  static const Vec3 white = xyz_to_linear_srgb(normalised_xyz({{kMinNm, kMaxNm}, {1.0, 1.0}}));
  const Vec3 rgb = xyz_to_linear_srgb(normalised_xyz(s));
  return min(max(Vec3(rgb.x / white.x, rgb.y / white.y, rgb.z / white.z), Vec3(0.0f)), Vec3(1.0f));
}

std::string parse_spectrum_pairs(const std::string& text, SampledSpectrum* out) {
  SampledSpectrum s;
  size_t start = 0;
  while (start <= text.size()) {
    size_t end = text.find(',', start);
    if (end == std::string::npos) end = text.size();
    const std::string pair = text.substr(start, end - start);
    const size_t colon = pair.find(':');
    double nm = 0, v = 0;
    if (colon == std::string::npos || !parse_double(pair.data(), pair.data() + colon, &nm) ||
        !parse_double(pair.data() + colon + 1, pair.data() + pair.size(), &v))
      return "'" + pair + "' is not a wavelength:value pair";
    if (!s.nm.empty() && !(nm > s.nm.back())) return "wavelengths must increase";
    s.nm.push_back(nm), s.value.push_back(v);
    start = end + 1;
  }
  *out = std::move(s);
  return "";
}

}  // namespace multiray::detail
