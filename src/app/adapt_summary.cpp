#include "app/adapt_summary.h"

#include <algorithm>
#include <cmath>

#include <fmt/core.h>

#include "core/file_io.h"

namespace multiray::app {

TargetingSummary targeting_summary(const std::vector<FrameRecord>& records, int warmup,
                                   double target_ms, const std::vector<ImageError>& errors) {
  TargetingSummary t;
  double sq = 0, pred_err = 0;
  int predicted = 0;
  for (size_t i = size_t(std::max(warmup, 0)); i < records.size(); ++i) {
    const FrameRecord& r = records[i];
    ++t.frames;
    sq += (r.frame_ms - target_ms) * (r.frame_ms - target_ms);
    t.worst_ratio = std::max(t.worst_ratio, r.frame_ms / target_ms);
    t.over_125 += r.frame_ms > 1.25 * target_ms;
    t.mean_step_scale += r.quality.step_scale;
    t.mean_image_scale += r.quality.image_scale;
    t.advise_ms += r.advise_ms;
    t.learn_ms += r.learn_ms;
    if (r.predicted_ms > 0 && r.frame_ms > 0) {
      pred_err += std::abs(r.predicted_ms - r.frame_ms) / r.frame_ms;
      ++predicted;
    }
  }
  if (t.frames == 0) return t;
  const double n = t.frames;
  t.rmse_ms = std::sqrt(sq / n);
  t.over_125 /= n, t.mean_step_scale /= n, t.mean_image_scale /= n, t.advise_ms /= n;
  t.learn_ms /= n;
  if (predicted > 0) t.prediction_error = pred_err / predicted;
  std::vector<int> known;
  for (size_t i = size_t(std::max(warmup, 0)); i < records.size(); ++i) {
    const FrameRecord& r = records[i];
    for (size_t d = 0; d < r.predicted_cost.size() && d < r.measured_cost.size(); ++d) {
      if (t.cost_error.size() <= d) t.cost_error.resize(d + 1, 0), known.resize(d + 1, 0);
      if (r.predicted_cost[d] > 0 && r.measured_cost[d] > 0) {
        t.cost_error[d] += std::abs(r.predicted_cost[d] - r.measured_cost[d]) / r.measured_cost[d];
        ++known[d];
      }
    }
  }
  for (size_t d = 0; d < t.cost_error.size(); ++d)
    t.cost_error[d] = known[d] > 0 ? t.cost_error[d] / known[d] : -1;
  double mse = 0, psnr = 0, ssim = 0;
  int compared = 0, finite = 0;
  for (size_t i = size_t(std::max(warmup, 0)); i < errors.size(); ++i) {
    mse += errors[i].mse, ssim += errors[i].ssim, ++compared;
    if (std::isfinite(errors[i].psnr_db)) psnr += errors[i].psnr_db, ++finite;
  }
  if (compared > 0) t.mse = mse / compared, t.ssim = ssim / compared;
  if (finite > 0) t.psnr_db = psnr / finite;
  return t;
}

nlohmann::json targeting_to_json(const TargetingSummary& t) {
  return {{"frames", t.frames},
          {"rmse_ms", t.rmse_ms},
          {"worst_frame_over_target", t.worst_ratio},
          {"share_over_1.25x_target", t.over_125},
          {"mean_step_scale", t.mean_step_scale},
          {"mean_image_scale", t.mean_image_scale},
          {"mean_prediction_error", t.prediction_error},
          {"mean_cost_prediction_error_per_device", t.cost_error},
          {"mean_advise_ms", t.advise_ms},
          {"mean_learn_ms", t.learn_ms},
          {"mse_vs_full_quality", t.mse},
          {"psnr_db_vs_full_quality", t.psnr_db},
          {"ssim_vs_full_quality", t.ssim}};
}

void print_targeting(const std::vector<std::string>& lanes,
                     const std::vector<TargetingSummary>& summaries, double target_ms) {
  fmt::print("\nframe-time target {:.1f} ms (frame times: engine wall time per frame)\n",
             target_ms);
  fmt::print("{:<40} {:>9} {:>8} {:>8} {:>7} {:>7} {:>9} {:>10} {:>8} {:>6}\n", "run", "RMSE ms",
             "worst", ">1.25x", "step x", "image x", "pred err", "predict ms", "PSNR dB", "SSIM");
  for (size_t i = 0; i < lanes.size() && i < summaries.size(); ++i) {
    const TargetingSummary& t = summaries[i];
    fmt::print("{:<40} {:9.1f} {:7.2f}x {:7.1f}% {:7.2f} {:7.2f} {:>9} {:10.2f} {:>8} {:>6}\n",
               lanes[i], t.rmse_ms, t.worst_ratio, 100 * t.over_125, t.mean_step_scale,
               t.mean_image_scale,
               t.prediction_error < 0 ? std::string("-")
                                      : fmt::format("{:.1f}%", 100 * t.prediction_error),
               t.advise_ms + t.learn_ms,
               t.psnr_db < 0 ? std::string("-") : fmt::format("{:.1f}", t.psnr_db),
               t.ssim < 0 ? std::string("-") : fmt::format("{:.3f}", t.ssim));
  }
}

namespace {
const char* lane_colour(size_t i) {
  static const char* kColours[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd",
                                   "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"};
  return kColours[i % 10];
}

// A "nice" axis maximum at or above x: 1, 2 or 5 times a power of ten.
double nice_ceiling(double x) {
  const double p = std::pow(10.0, std::floor(std::log10(std::max(x, 1e-9))));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * p >= x) return m * p;
  return 10 * p;
}
}  // namespace

void write_targeting_svg(const std::string& path, const std::string& title,
                         const std::vector<std::string>& lanes,
                         const std::vector<std::vector<FrameRecord>>& records, double target_ms,
                         const std::vector<int>& switches) {
  size_t n = 0;
  double t_max = 2 * target_ms, s_max = 1;
  for (const auto& lane : records) {
    n = std::max(n, lane.size());
    for (const FrameRecord& r : lane)
      t_max = std::max(t_max, r.frame_ms), s_max = std::max(s_max, r.quality.step_scale);
  }
  if (n == 0) return;
  t_max = nice_ceiling(t_max), s_max = nice_ceiling(s_max);
  const double W = 900, left = 60, plot_w = W - left - 20, top = 40, h1 = 260, h2 = 120, gap = 50,
               H = top + h1 + gap + h2 + 50;
  auto x_of = [&](double f) { return left + (n > 1 ? f / double(n - 1) : 0.5) * plot_w; };
  std::string svg = fmt::format(
      "<svg xmlns='http://www.w3.org/2000/svg' width='{}' height='{}' font-family='sans-serif' "
      "font-size='12'>\n<rect width='100%' height='100%' fill='white'/>\n"
      "<text x='{}' y='20' font-size='15'>{}</text>\n",
      W, H, left, title);
  auto axis = [&](double y0, double h, double max, const char* label, const char* fmt_str) {
    for (int k = 0; k <= 4; ++k) {
      const double y = y0 + h * (1 - k / 4.0);
      svg += fmt::format(
          "<line x1='{}' y1='{}' x2='{}' y2='{}' stroke='#ddd'/><text x='{}' y='{}' "
          "text-anchor='end'>{}</text>\n",
          left, y, left + plot_w, y, left - 5, y + 4,
          fmt::format(fmt::runtime(fmt_str), max * k / 4));
    }
    svg += fmt::format("<text x='15' y='{}' transform='rotate(-90 15 {})'>{}</text>\n", y0 + h / 2,
                       y0 + h / 2, label);
  };
  axis(top, h1, t_max, "frame time (ms)", "{:.0f}");
  axis(top + h1 + gap, h2, s_max, "step x", "{:g}");
  for (int f : switches)
    svg += fmt::format(
        "<line x1='{0}' y1='{1}' x2='{0}' y2='{2}' stroke='#999' stroke-dasharray='2,3'/>"
        "<text x='{0}' y='{3}' text-anchor='middle' fill='#666'>TF</text>\n",
        x_of(f), top, top + h1 + gap + h2, top - 4);
  const double ty = top + h1 * (1 - target_ms / t_max);
  svg += fmt::format(
      "<line x1='{}' y1='{}' x2='{}' y2='{}' stroke='black' stroke-dasharray='6,4'/>"
      "<text x='{}' y='{}' text-anchor='end'>target {:.0f} ms</text>\n",
      left, ty, left + plot_w, ty, left + plot_w, ty - 4, target_ms);
  for (size_t l = 0; l < records.size(); ++l) {
    std::string time_pts, step_pts;
    for (size_t i = 0; i < records[l].size(); ++i) {
      const FrameRecord& r = records[l][i];
      time_pts +=
          fmt::format("{:.1f},{:.1f} ", x_of(double(i)), top + h1 * (1 - r.frame_ms / t_max));
      step_pts += fmt::format("{:.1f},{:.1f} ", x_of(double(i)),
                              top + h1 + gap + h2 * (1 - r.quality.step_scale / s_max));
    }
    for (const std::string* pts : {&time_pts, &step_pts})
      svg += fmt::format("<polyline fill='none' stroke='{}' stroke-width='1.3' points='{}'/>\n",
                         lane_colour(l), *pts);
    svg += fmt::format(
        "<rect x='{}' y='{}' width='10' height='10' fill='{}'/><text x='{}' y='{}'>{}</text>\n",
        left + 10, top + 8 + 16 * double(l), lane_colour(l), left + 25, top + 17 + 16 * double(l),
        l < lanes.size() ? lanes[l] : "");
  }
  svg += fmt::format("<text x='{}' y='{}' text-anchor='middle'>frame</text>\n</svg>\n",
                     left + plot_w / 2, H - 10);
  write_file_atomically(path, svg);
}

}  // namespace multiray::app
