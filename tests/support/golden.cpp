#include "support/golden.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

namespace multiray::testing {

bool GoldenVerdict::pass() const {
  if (!problem.empty()) return false;
  for (const GoldenStatistic& s : statistics)
    if (!s.pass()) return false;
  return true;
}

std::string GoldenVerdict::summary() const {
  if (!problem.empty()) return problem;
  std::string out;
  for (const GoldenStatistic& s : statistics)
    out += fmt::format("{}{} {:.4g} (limit {:.4g}{})", out.empty() ? "" : ", ", s.name, s.value,
                       s.limit, s.pass() ? "" : ", FAILS");
  return out;
}

namespace {

constexpr double kClip = 4;  // a block's z counts at most this much (see golden.h)

// z of every block of b x b pixels and every channel. Where the reference never varied
// (var 0: sky, an unlit wall), the difference must be zero up to float rounding, else the
// block counts as far out as the clip allows.
std::vector<double> block_z(const Framebuffer& x, const GoldenReference& ref, int b) {
  const int nx = (x.width + b - 1) / b, ny = (x.height + b - 1) / b;
  std::vector<double> diff(size_t(nx * ny * 3)), var(diff.size()), size(diff.size());
  const double inflate = 1.0 + 1.0 / double(ref.renders);  // the reference mean's noise
  for (int y = 0; y < x.height; ++y)
    for (int xx = 0; xx < x.width; ++xx)
      for (int c = 0; c < 3; ++c) {
        const size_t k = size_t(((y / b) * nx + xx / b) * 3 + c);
        diff[k] += double(x.at(xx, y)[c]) - double(ref.mean.at(xx, y)[c]);
        var[k] += inflate * double(ref.var.at(xx, y)[c]);
        size[k] += std::abs(double(ref.mean.at(xx, y)[c]));
      }
  std::vector<double> z(diff.size());
  for (size_t k = 0; k < z.size(); ++k)
    z[k] = var[k] > 0                                           ? diff[k] / std::sqrt(var[k])
           : std::abs(diff[k]) <= 1e-5 * std::max(1.0, size[k]) ? 0.0
                                                                : std::copysign(kClip, diff[k]);
  return z;
}

double clipped_squares(const std::vector<double>& z) {
  double sum = 0;
  for (double v : z) sum += std::min(v * v, kClip * kClip);
  return sum;
}

double mean_shift(const std::vector<double>& z) {
  double worst = 0;
  for (size_t c = 0; c < 3; ++c) {
    double sum = 0;
    for (size_t k = c; k < z.size(); k += 3) sum += std::clamp(z[k], -kClip, kClip);
    worst = std::max(worst, std::abs(sum) / std::sqrt(double(z.size() / 3)));
  }
  return worst;
}

}  // namespace

GoldenVerdict compare_to_golden(const Framebuffer& image, const GoldenReference& ref) {
  GoldenVerdict v;
  if (image.width != ref.mean.width || image.height != ref.mean.height ||
      ref.var.width != ref.mean.width || ref.var.height != ref.mean.height || ref.renders < 2) {
    v.problem =
        fmt::format("image {}x{} against a reference of {}x{} from {} renders", image.width,
                    image.height, ref.mean.width, ref.mean.height, ref.renders);
    return v;
  }
  for (const Vec3& p : image.pixels)
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      v.problem = "the image has a non-finite pixel";
      return v;
    }
  const std::vector<double> z2 = block_z(image, ref, 2), z8 = block_z(image, ref, 8);
  const std::pair<std::string, double> values[] = {
      {"blocks 2x2", clipped_squares(z2)},
      {"blocks 8x8", clipped_squares(z8)},
      {"mean shift", mean_shift(z8)},
  };
  for (const auto& [name, value] : values) {
    const auto it = ref.null.find(name);
    v.statistics.push_back({name, value, it == ref.null.end() ? 0.0 : it->second.limit()});
  }
  return v;
}

std::map<std::string, NullDistribution> null_of(const std::vector<GoldenVerdict>& verdicts) {
  std::map<std::string, std::vector<double>> values;
  for (const GoldenVerdict& v : verdicts)
    for (const GoldenStatistic& s : v.statistics) values[s.name].push_back(s.value);
  std::map<std::string, NullDistribution> out;
  for (const auto& [name, xs] : values) {
    double mean = 0, ss = 0;
    for (double x : xs) mean += x / double(xs.size());
    for (double x : xs) ss += (x - mean) * (x - mean);
    out[name] = {mean, xs.size() > 1 ? std::sqrt(ss / double(xs.size() - 1)) : 0.0};
  }
  return out;
}

void GoldenAccumulator::add(const Framebuffer& fb) {
  if (n_ == 0) {
    width_ = fb.width, height_ = fb.height;
    mean_.assign(fb.pixels.size() * 3, 0.0), m2_.assign(mean_.size(), 0.0);
  }
  ++n_;
  for (size_t i = 0; i < fb.pixels.size() && 3 * i < mean_.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const size_t k = 3 * i + size_t(c);
      const double x = fb.pixels[i][c], d = x - mean_[k];
      mean_[k] += d / n_;
      m2_[k] += d * (x - mean_[k]);
    }
}

GoldenReference GoldenAccumulator::reference() const {
  GoldenReference r{Framebuffer(width_, height_), Framebuffer(width_, height_), n_, {}};
  for (size_t i = 0; i < r.mean.pixels.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      r.mean.pixels[i][c] = float(mean_[3 * i + size_t(c)]);
      r.var.pixels[i][c] = n_ > 1 ? float(m2_[3 * i + size_t(c)] / (n_ - 1)) : 0.0f;
    }
  return r;
}

void write_golden(const std::string& stem, const GoldenReference& ref) {
  write_exr(stem + ".mean.exr", ref.mean);
  write_exr(stem + ".var.exr", ref.var);
}

GoldenReference read_golden(const std::string& stem, int renders,
                            const std::map<std::string, NullDistribution>& null) {
  return {read_exr(stem + ".mean.exr"), read_exr(stem + ".var.exr"), renders, null};
}

}  // namespace multiray::testing
