#include "study/bench_outputs.h"

#include <fmt/core.h>

#include "balance/balancer.h"
#include "core/console.h"
#include "study/adapt_summary.h"
#include "study/stats_json.h"
#include "study/trace_file.h"

namespace multiray::study {

void print_run_header(const Run& s, const RunConfig& o, const std::vector<std::string>& labels) {
  const SamplingSetup& sampling = s.views->sampling();
  print_out(
      "scene {}, {}x{} x {} views, {} kernel, {} sampling ({}), {} frames, camera path "
      "{}\n",
      s.scene->name, s.res.width, s.res.height, s.views->rig().view_count(), s.settings.kernel,
      o.sampling,
      sampling.mode == Sampling::Adaptive ? fmt::format("{} spp on edges, 1 elsewhere", o.edge_spp)
      : sampling.mode == Sampling::Foveated
          ? fmt::format("{:g} spp at the gaze, {:g} in the periphery, "
                        "{} pattern samples, gaze path {}",
                        o.foveation.fovea_spp, o.foveation.periphery_spp,
                        sampling.pattern->offsets.size(), o.gaze_path)
      : sampling.mode == Sampling::Reprojected
          ? fmt::format("{} spp on the references and on holes", s.settings.spp)
          : std::to_string(s.settings.spp) + " spp",
      o.frames, o.camera_path);
  for (const auto& l : labels) print_out("  device {}\n", l);
}

nlohmann::json lane_outputs(size_t k, const Run& s, const BenchResult& result,
                            const std::vector<std::string>& lanes,
                            const std::vector<std::string>& labels, const RunSummary& summary,
                            const std::vector<uint32_t>& reference_views, bool mixed_types,
                            const TimelineScale& timeline, int warmup, int partition_frame,
                            const BenchOptions& b, bool with_frames, std::string name) {
  const BenchLane& lane = result.lanes[k];
  const std::vector<int>& mismatched = result.mismatched_frames[k];
  nlohmann::json frames = nlohmann::json::array();
  for (size_t f = 0; with_frames && f < lane.records.size(); ++f) {
    frames.push_back(frame_to_json(lane.records[f]));
    frames.back()["sampling_ms"] = result.sampling_ms[f];
    if (f < result.hole_fraction.size())
      frames.back()["reprojection"] =
          reprojection_to_json(reference_views, result.hole_fraction[f]);
    frames.back()["image_hash"] = fmt::format("{:016x}", lane.image_hashes[f]);
  }
  if (s.volume && s.volume->modes().size() > 1)
    name +=
        std::string("-") + balance::adapt_name(s.volume->modes()[k % s.volume->modes().size()]);
  nlohmann::json run{
      {"balancer", lane.spec},
      {"lane", lanes[k]},
      {"devices", devices_to_json(s.devices)},
      {"image_matches_first_run", mixed_types ? nlohmann::json("not compared: mixed device types")
                                              : nlohmann::json(mismatched.empty())},
      {"mismatched_frames", mismatched},
      {"frames", frames},
      {"summary", summary_to_json(summary, warmup, result.sampled)}};
  if (s.volume && s.volume->options().target_ms > 0)
    run["targeting"] = targeting_to_json(targeting_summary(
        lane.records, warmup, s.volume->options().target_ms, lane.error_vs_reference));
  if (!b.trace_prefix.empty()) {
    TraceFile trace(fmt::format("{}-{}.trace", b.trace_prefix, name), lane.spec, s.devices);
    for (size_t k = 0; k < lane.stats.size(); ++k)
      trace.frame(lane.stats[k], k < lane.records.size()
                                     ? lane.records[k].models
                                     : std::vector<balance::DeviceCostModel>{});
    trace.close();
  }
  if (!b.report_dir.empty()) {
    const std::string png = fmt::format("{}_partition.png", name);
    write_partition_png(b.report_dir + "/" + png, s.res.width, s.res.height, lane.partition,
                        &lane.partition_image);
    write_partition_svg(
        fmt::format("{}/{}_partition.svg", b.report_dir, name), png,
        fmt::format("frame {}, view 0, who rendered what — {}", partition_frame, lane.spec),
        s.res.width, s.res.height, labels);
    write_timeline_svg(fmt::format("{}/{}_timeline.svg", b.report_dir, name),
                       fmt::format("{} — {} ({}x{}, {} spp)", lane.spec, s.scene->name,
                                   s.res.width, s.res.height, s.settings.spp),
                       lane.records, labels, timeline);
  }
  return run;
}

void report_volume(const Run& s, const BenchResult& result, const std::vector<std::string>& lanes,
                   const std::vector<std::string>& labels, int warmup,
                   const std::string& report_dir, bool quiet) {
  if (!quiet) {
    std::string styles;
    for (double ms : s.volume->style_ms)
      styles += fmt::format("{}{:.1f}", styles.empty() ? "" : ", ", ms);
    print_out(
        "volume set-up (host, wall time): block histograms {:.1f} ms once; table and "
        "opacity histograms per transfer function {} ms\n",
        s.volume->blocks_ms, styles);
  }
  if (s.volume && s.volume->options().target_ms > 0) {
    std::vector<TargetingSummary> t;
    for (const BenchLane& lane : result.lanes)
      t.push_back(targeting_summary(lane.records, warmup, s.volume->options().target_ms,
                                    lane.error_vs_reference));
    if (!quiet) print_targeting(lanes, t, s.volume->options().target_ms);
    if (!report_dir.empty()) {
      std::vector<std::vector<FrameRecord>> records;
      for (const BenchLane& lane : result.lanes) records.push_back(lane.records);
      std::vector<int> switches;
      if (const InteractionSequence* seq = s.volume->sequence())
        for (const auto& [frame, tf] : seq->transfer_functions)
          if (frame > 0) switches.push_back(frame);
      write_targeting_svg(report_dir + "/targeting.svg",
                          fmt::format("frame time vs target — {} ({}x{})", s.scene->name,
                                      s.res.width, s.res.height),
                          lanes, records, s.volume->options().target_ms, switches);
      // The sigma panel follows the predicting lane (the last one if none predicts).
      size_t cost_lane = lanes.size() - 1;
      for (size_t l = 0; l < lanes.size(); ++l)
        if (lanes[l].find("adapt=predict") != std::string::npos) cost_lane = l;
      write_prediction_svg(
          report_dir + "/prediction.svg",
          fmt::format("prediction error — {} ({}x{})", s.scene->name, s.res.width, s.res.height),
          lanes, records, cost_lane, labels, switches);
    }
  }
}

nlohmann::json run_description(const Run& s, const RunConfig& o) {
  return {{"scene", s.scene->name},
          {"resolution", {s.res.width, s.res.height}},
          {"views", s.views->rig().view_count()},
          {"spp", s.settings.spp},
          {"integrator", s.settings.kernel},
          {"sampling", o.sampling},
          {"frames", o.frames},
          {"camera_path", o.camera_path},
          {"timing",
           "device_ms measured inside each device (steady_clock); frame_ms by the engine "
           "around all devices"},
          {"volume_setup_ms", s.volume ? nlohmann::json{{"block_histograms", s.volume->blocks_ms},
                                                        {"styles", s.volume->style_ms}}
                                       : nlohmann::json()}};
}

}  // namespace multiray::study
