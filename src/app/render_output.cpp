#include "app/render_output.h"

#include <algorithm>

#include <fmt/core.h>

#include "app/commands.h"
#include "core/aov_exr.h"
#include "core/console.h"
#include "core/exposure.h"
#include "study/adapt_summary.h"
#include "study/split_overlay.h"
#include "study/stats_json.h"

namespace multiray::app {

RenderOutput::RenderOutput(OutputTarget target, bool fixed_exposure, bool quiet, int columns,
                           const Display& display, study::TraceFile* trace)
    : target_(std::move(target)),
      records_(target_.dir),
      fixed_exposure_(fixed_exposure),
      quiet_(quiet),
      columns_(columns),
      display_(display),
      trace_(trace) {}

void RenderOutput::write_images(const FrameResult& r) {
  const auto& images = r.images;
  const bool views = images.size() > 1;
  for (size_t v = 0; v < images.size(); ++v) {
    const std::string tag = views ? fmt::format("_view{:02d}", v) : "";
    const std::string name = target_.image_base(r.frame, tag);
    const Framebuffer* image = &images[v];
    Framebuffer composite;
    if (!image->alpha.empty()) {  // an RGBA layer: it, and the composite as the image
      const std::string layer = target_.image_base(r.frame, tag + "_rgba");
      if (target_.png) write_png_rgba(layer + ".png", *image, display_);
      if (target_.exr) write_exr(layer + ".exr", *image);  // RGBA
      if (background_) {
        composite = composite_over(*image, background_->frame(r.frame));
        image = &composite;
      }
    }
    // The denoised image (Session::set_denoise), with the raw one's feature buffers.
    const Framebuffer& shown = v < r.denoised.size() ? r.denoised[v] : *image;
    // The EXR's layers need the raw image's feature buffers beside a denoised beauty: only
    // then is the denoised image copied.
    Framebuffer with_features;
    if (denoised_exr_ && !aovs_.empty() && &shown != image) {
      with_features = shown;
      with_features.features = image->features;
    }
    const Framebuffer& kept = !denoised_exr_            ? *image
                              : with_features.width > 0 ? with_features
                                                        : shown;
    if (target_.png) write_png(name + ".png", shown, display_);
    if (!aovs_.empty())  // the beauty and its AOVs as layers of one EXR (core/aov_exr.h)
      write_exr_with_aovs(
          target_.exr ? name + ".exr" : target_.image_base(r.frame, tag + "_aov") + ".exr", kept,
          aovs_);
    else if (target_.exr)
      write_exr(name + ".exr", kept);
    if (overlay_) write_overlay(r, v, shown, tag);
  }
  if (views) {
    const Framebuffer quilt = make_quilt(images, columns_);
    const std::string name = target_.image_base(r.frame, "_quilt");
    // The quilt is for looking at: a PNG, or an EXR where only EXR files are asked for.
    if (target_.png)
      write_png(name + ".png", quilt, display_);
    else
      write_exr(name + ".exr", quilt);
  }
}

void RenderOutput::write_overlay(const FrameResult& r, size_t view, const Framebuffer& image,
                                 const std::string& tag) {
  study::Rgb8Image frame{image.width, image.height, to_srgb8(image, display_)};
  std::vector<study::OverlayDevice> devices;
  double samples = 0;
  for (const auto& d : r.stats.devices) samples += d.samples;
  for (size_t d = 0; d < r.stats.devices.size(); ++d) {
    const balance::DeviceFrameStats& s = r.stats.devices[d];
    study::OverlayDevice o;
    o.name = d < device_names_.size() ? device_names_[d] : fmt::format("device {}", d);
    for (const auto& it : s.items)
      if (size_t(it.item.view) == view) o.rects.push_back(it.item.rect);
    o.share = samples > 0 ? s.samples / samples : 0;
    o.busy_ms = s.busy_ms;
    o.left_out = s.rested;
    devices.push_back(std::move(o));
  }
  const std::string title = fmt::format("frame {}: {:.0f} ms, imbalance {:.1f}%", r.frame,
                                        r.record.frame_ms, 100 * r.record.imbalance);
  const study::Rgb8Image out = study::split_overlay(frame, devices, title);
  last_overlay_ = target_.image_base(r.frame, tag + "_split") + ".png";
  write_png_rgb8(last_overlay_, out.width, out.height, out.rgb);
}

void RenderOutput::add_to_summary(const FrameResult& r) {
  const size_t n = r.stats.devices.size();
  sum_samples_.resize(n, 0), sum_busy_.resize(n, 0), took_part_.resize(n, 0);
  for (size_t d = 0; d < n; ++d) {
    const balance::DeviceFrameStats& s = r.stats.devices[d];
    if (s.rested || !s.alive) continue;
    sum_samples_[d] += s.samples;
    sum_busy_[d] += s.busy_ms;
    ++took_part_[d];
  }
  sum_imbalance_ += r.record.imbalance;
  ++summary_frames_;
}

std::string RenderOutput::balance_summary() const {
  if (summary_frames_ == 0 || sum_samples_.empty()) return "";
  if (sum_samples_.size() == 1)
    return fmt::format(
        "balance: one device ({}) rendered everything, nothing to split (`multiray devices` "
        "lists what else this machine offers; --devices takes several)\n",
        device_names_.empty() ? "cpu" : device_names_[0]);
  double samples = 0;
  for (double s : sum_samples_) samples += s;
  std::string out =
      fmt::format("balance over {} frame{}:\n", summary_frames_, summary_frames_ == 1 ? "" : "s");
  size_t width = 0;
  for (size_t d = 0; d < sum_samples_.size(); ++d)
    width = std::max(width, d < device_names_.size() ? device_names_[d].size() : 8);
  for (size_t d = 0; d < sum_samples_.size(); ++d) {
    const std::string name =
        d < device_names_.size() ? device_names_[d] : fmt::format("device {}", d);
    if (took_part_[d] == 0) {
      out += fmt::format("  {:<{}}  left out of every frame\n", name, width);
      continue;
    }
    out += fmt::format("  {:<{}}  {:5.1f}% of the samples  busy {:8.1f} ms a frame{}\n", name,
                       width, samples > 0 ? 100 * sum_samples_[d] / samples : 0.0,
                       sum_busy_[d] / took_part_[d],
                       took_part_[d] < summary_frames_
                           ? fmt::format(" (in {} of {} frames)", took_part_[d], summary_frames_)
                           : "");
  }
  out += fmt::format("  the devices finished within {:.1f}% of each other (mean imbalance)",
                     100 * sum_imbalance_ / summary_frames_);
  if (!last_overlay_.empty()) out += "; the split: " + last_overlay_;
  out += "\n";
  return out;
}

void RenderOutput::on_frame(const std::shared_ptr<const FrameResult>& r) {
  if (!fixed_exposure_ && !metered_ && !r->images.empty()) {
    display_.exposure_ev = metered_exposure_ev(
        r->images.size() > 1 ? make_quilt(r->images, columns_) : r->images.front());
    metered_ = true;
    if (!quiet_)
      print_err(
          "{}multiray: note: exposure {:+.1f} EV, metered on frame {} and held "
          "(--exposure auto; --exposure EV sets it)\n",
          stderr_is_tty() ? "\r\033[K" : "", display_.exposure_ev, r->frame);
  }
  write_images(*r);
  if (stderr_is_tty()) print_err("\r\033[K");
  const FrameRecord& rec = r->record;
  for (const auto& m : rec.messages) print_err("multiray: warning: {}\n", m);
  if (!quiet_)
    for (const auto& m : rec.notes) print_err("multiray: note: frame {}: {}\n", rec.frame, m);
  if (target_ms_ > 0)
    targeted_frames_.push_back({rec.quality.step_scale, rec.quality.image_scale, rec.frame_ms});
  if (target_ms_ > 0 && !warned_quality_) {
    const std::string w =
        study::degraded_quality_warning(targeted_frames_, target_ms_, lowest_cost_);
    if (!w.empty()) print_err("multiray: warning: {}\n", w);
    warned_quality_ = !w.empty();
  }
  uint64_t samples = 0, rays = 0;
  for (const auto& d : rec.devices) samples += d.samples, rays += d.rays;
  // Frame-time targeting: the predicted time and the quality the frame was rendered at.
  const std::string adapted =
      rec.predicted_ms > 0 || rec.quality.step_scale != 1 || rec.quality.image_scale != 1
          ? fmt::format("  predicted {:7.1f} ms  step x{:.2f}  image x{:.2f}", rec.predicted_ms,
                        rec.quality.step_scale, rec.quality.image_scale)
          : "";
  // Reprojected sampling: the share of the other views' pixels path-traced as holes.
  const std::string holes =
      r->reprojection ? fmt::format("  holes {:4.1f}%", 100.0 * r->reprojection->hole_fraction())
                      : "";
  const std::string shown = target_.image_base(r->frame, r->images.size() > 1 ? "_quilt" : "") +
                            (target_.png ? ".png" : ".exr");
  if (!quiet_)
    print_out(
        "frame {:4d}  {:9.1f} ms  {:7.2f} Msamples/s  {:7.2f} Mrays/s  imbalance {:5.1f}%{}{}  "
        "-> {}\n",
        r->frame, rec.frame_ms, samples / rec.frame_ms / 1e3, rays / rec.frame_ms / 1e3,
        100.0 * rec.imbalance, adapted, holes, shown);
  add_to_summary(*r);
  records_.add(study::frame_result_to_json(*r));
  if (trace_) trace_->frame(r->stats, r->record.models);
  counters_.samples += samples;
  counters_.frame_us += uint64_t(std::max(0.0, rec.frame_ms) * 1e3);
  counters_.frames += 1;
}

}  // namespace multiray::app
