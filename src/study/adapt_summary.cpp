#include "study/adapt_summary.h"

#include <algorithm>
#include <cmath>

#include <fmt/core.h>

#include "core/console.h"
#include "study/svg_chart.h"

namespace multiray::study {

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
  print_out("\nframe-time target {:.1f} ms (frame times: engine wall time per frame)\n",
            target_ms);
  print_out("{:<40} {:>9} {:>8} {:>8} {:>7} {:>7} {:>9} {:>10} {:>8} {:>6}\n", "run", "RMSE ms",
            "worst", ">1.25x", "step x", "image x", "pred err", "predict ms", "PSNR dB", "SSIM");
  for (size_t i = 0; i < lanes.size() && i < summaries.size(); ++i) {
    const TargetingSummary& t = summaries[i];
    print_out("{:<40} {:9.1f} {:7.2f}x {:7.1f}% {:7.2f} {:7.2f} {:>9} {:10.2f} {:>8} {:>6}\n",
              lanes[i], t.rmse_ms, t.worst_ratio, 100 * t.over_125, t.mean_step_scale,
              t.mean_image_scale,
              t.prediction_error < 0 ? std::string("-")
                                     : fmt::format("{:.1f}%", 100 * t.prediction_error),
              t.advise_ms + t.learn_ms,
              t.psnr_db < 0 ? std::string("-") : fmt::format("{:.1f}", t.psnr_db),
              t.ssim < 0 ? std::string("-") : fmt::format("{:.3f}", t.ssim));
  }
}

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
  SvgChart chart(title, n);
  const int times = chart.add_panel("frame time (ms)", t_max, 260, "{:.0f}");
  const int steps = chart.add_panel("step x", s_max, 120);
  for (int f : switches) chart.mark(f, "TF");
  chart.reference(times, target_ms, fmt::format("target {:g} ms", target_ms));
  std::vector<std::pair<std::string, const char*>> legend;
  for (size_t l = 0; l < records.size(); ++l) {
    std::vector<double> ms, step;
    for (const FrameRecord& r : records[l])
      ms.push_back(r.frame_ms), step.push_back(r.quality.step_scale);
    chart.line(times, ms, series_colour(l));
    chart.line(steps, step, series_colour(l));
    legend.emplace_back(l < lanes.size() ? lanes[l] : "", series_colour(l));
  }
  chart.legend(times, legend);
  chart.write(path);
}

void write_prediction_svg(const std::string& path, const std::string& title,
                          const std::vector<std::string>& lanes,
                          const std::vector<std::vector<FrameRecord>>& records, size_t cost_lane,
                          const std::vector<std::string>& devices,
                          const std::vector<int>& switches) {
  auto error_pct = [](double predicted, double measured) {
    return predicted > 0 && measured > 0 ? 100 * std::abs(predicted - measured) / measured : NAN;
  };
  // Single frames vary by 10-20% on a shared machine: a centred 9-frame mean shows the trend.
  auto smooth = [](const std::vector<double>& x) {
    std::vector<double> out(x.size(), NAN);
    for (size_t i = 0; i < x.size(); ++i) {
      double sum = 0;
      int n = 0;
      for (size_t j = i >= 4 ? i - 4 : 0; j <= i + 4 && j < x.size(); ++j)
        if (std::isfinite(x[j])) sum += x[j], ++n;
      if (n > 0) out[i] = sum / n;
    }
    return out;
  };
  size_t n = 0;
  for (const auto& lane : records) n = std::max(n, lane.size());
  if (n == 0) return;
  SvgChart chart(title, n);
  // Errors above 100% are drawn at the top: the interesting range is 0-100%.
  const int frame = chart.add_panel("frame time error (%, 9-frame mean)", 100, 200, "{:.0f}");
  const int cost = chart.add_panel("cost/sample error (%, 9-frame mean)", 100, 200, "{:.0f}");
  for (int f : switches) chart.mark(f, "TF");
  std::vector<std::pair<std::string, const char*>> lane_legend, device_legend;
  for (size_t l = 0; l < records.size(); ++l) {
    std::vector<double> e;
    for (const FrameRecord& r : records[l]) e.push_back(error_pct(r.predicted_ms, r.frame_ms));
    chart.line(frame, smooth(e), series_colour(l));
    lane_legend.emplace_back(l < lanes.size() ? lanes[l] : "", series_colour(l));
  }
  if (cost_lane < records.size())
    for (size_t d = 0; d < devices.size(); ++d) {
      std::vector<double> e;
      for (const FrameRecord& r : records[cost_lane])
        e.push_back(d < r.predicted_cost.size() && d < r.measured_cost.size()
                        ? error_pct(r.predicted_cost[d], r.measured_cost[d])
                        : NAN);
      // Devices in the colours after the lanes', so the two panels are not confused.
      chart.line(cost, smooth(e), series_colour(records.size() + d));
      device_legend.emplace_back(devices[d] + " (" + lanes.at(cost_lane) + ")",
                                 series_colour(records.size() + d));
    }
  chart.legend(frame, lane_legend);
  chart.legend(cost, device_legend);
  chart.write(path);
}

FrameTimeFit fit_frame_time(const std::vector<QualityTime>& frames) {
  FrameTimeFit f;
  double n = 0, sc = 0, st = 0, scc = 0, sct = 0;
  for (const QualityTime& q : frames) {
    const double c = q.cost();
    if (!(q.frame_ms > 0) || !std::isfinite(q.frame_ms) || !(c > 0) || !std::isfinite(c)) continue;
    n += 1, sc += c, st += q.frame_ms, scc += c * c, sct += c * q.frame_ms;
  }
  const double var = n * scc - sc * sc;  // n² times the variance of c
  if (n < 2 || !(var > 1e-12 * n * n)) return f;
  f.work_ms = (n * sct - sc * st) / var;
  f.fixed_ms = (st - f.work_ms * sc) / n;
  if (!(f.work_ms > 0)) return f;
  // A negative intercept (noise) would promise the impossible at coarse quality: take the
  // line through the origin's side instead, no fixed part.
  if (f.fixed_ms < 0) f.fixed_ms = 0, f.work_ms = sct / scc;
  f.ok = true;
  return f;
}

std::string degraded_quality_warning(const std::vector<QualityTime>& frames, double target_ms,
                                     double lowest_cost) {
  if (frames.empty() || !(target_ms > 0)) return "";
  const QualityTime& last = frames.back();
  const double cost = last.cost();
  if (!(cost < kVisibleCost) || !(last.frame_ms > 0)) return "";
  const FrameTimeFit fit = fit_frame_time(frames);
  double full_ms = 0;  // the slowest full-quality frame measured
  for (const QualityTime& q : frames)
    if (q.cost() >= 1) full_ms = std::max(full_ms, q.frame_ms);
  double keep_ms = std::max(target_ms, last.frame_ms) * kVisibleCost / cost;
  std::string how = "time taken as proportional to the work";
  if (fit.ok) {
    keep_ms = fit.at(kVisibleCost);
    how = fmt::format("fitted to this run's frames: {:.0f} ms fixed + {:.0f} ms at full work",
                      fit.fixed_ms, fit.work_ms);
  }
  if (full_ms > 0) {
    keep_ms = std::min(keep_ms, full_ms);
    how += fmt::format("; a full-quality frame took {:.0f} ms", full_ms);
  }
  std::string line = fmt::format(
      "--target-ms {:g} made a frame do {:.0f}x less than the full work (step x{:.2f}, image "
      "x{:.2f}); past {:.0f}x it shows as slabs and blur. About --target-ms {:.0f} keeps it "
      "within {:.0f}x ({}), or add devices",
      target_ms, 1.0 / cost, last.step_scale, last.image_scale, 1.0 / kVisibleCost,
      std::ceil(keep_ms), 1.0 / kVisibleCost, how);
  if (fit.ok && lowest_cost > 0 && fit.at(lowest_cost) > target_ms)
    line += fmt::format(
        ". Even the coarsest quality allowed ({:.0f}x less work) takes about {:.0f} ms here: "
        "--target-ms {:g} cannot be met",
        1.0 / lowest_cost, fit.at(lowest_cost), target_ms);
  return line;
}

}  // namespace multiray::study
