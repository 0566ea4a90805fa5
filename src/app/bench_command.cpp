// `multiray bench`: its options (render's and its own); the run is study/bench_run.h's.
#include <memory>

#include "app/commands.h"
#include "study/bench_run.h"

namespace multiray::app {

Runner add_bench_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "bench", "Run several balancers on the same frames and compare how evenly devices finish");
  auto o = std::make_shared<RunConfig>(study::bench_defaults());
  auto b = std::make_shared<study::BenchOptions>();
  add_common_options(*cmd, *o);
  cmd->add_option("--balancers", b->balancers,
                  "Comma-separated balancer specs to compare (default: every balancer; "
                  "`render --help` lists them with their options)")
      ->capture_default_str();
  cmd->add_option("--json", b->json_path, "Write all measurements as JSON to this file");
  cmd->add_option("--denoise", o->denoise,
                  "Denoise every frame after the gather: none, atrous or svgf (docs/noise.md); "
                  "its time is in the host column of \"where the time goes\"")
      ->capture_default_str();
  cmd->add_flag("--regret", b->regret,
                "The default balancer (auto) against every subset of --devices: each device "
                "alone, ..., all of them (subset lanes, instead of --balancers); prints the "
                "regret, the default's frame time over the best subset's, with its interval");
  cmd->add_option("--lane-order", b->lane_order,
                  "rotate: frame f starts with the f-th balancer and goes round, so each renders "
                  "first equally often (the first of a frame runs 1-5% slower on colder caches); "
                  "fixed: the order of --balancers in every frame, as benches before 2026-12-04 "
                  "ran (--regret keeps an order of its own)")
      ->capture_default_str();
  cmd->add_option(
      "--report", b->report_dir,
      "Folder for plots: comparison.svg (efficiency, imbalance and frame time of every "
      "balancer), <balancer>_timeline.svg (device times on one scale for all "
      "balancers, shares with the ideal split, warm-up shaded), "
      "<balancer>_partition.png");
  cmd->add_option("--trace", b->trace_prefix,
                  "Write one trace per balancer, PREFIX-<balancer>.trace: every work item's "
                  "device, view, rect, samples, busy and wall time (format: docs/traces.md)");
  CLI::Option* warmup_option =
      cmd->add_option("--warmup", b->warmup,
                      "Frames left out of the summary (balancers settling); default min(10, "
                      "frames / 4), so short runs work without it");
  cmd->add_option("--ideal-frames", b->ideal_frames,
                  "Frames (spread over those after --warmup) on which each device is timed alone; "
                  "efficiency = sum of ideal times (interpolated between those frames) / sum of "
                  "actual frame times, over the frames after --warmup")
      ->capture_default_str();
  cmd->add_option("--repeats", b->repeats,
                  "Repeat blocks: the whole run K times, each a fresh start of every balancer "
                  "over the same frames; frame time and efficiency are then reported as medians "
                  "with 95% intervals, and a balancer is named faster only where the intervals "
                  "of its per-frame ratios separate (1: one block, no intervals)")
      ->capture_default_str();
  CLI::Option* repeats_option = cmd->get_option("--repeats");
  cmd->add_option("--reference-step", o->volume.reference_step,
                  "Volumes: render every frame once more at this step (voxel lengths, on device "
                  "0, outside the timings) as the reference of every lane's PSNR/SSIM (Bruder "
                  "et al.'s Table 4: 0.1); 0: the first lane's full-quality frames")
      ->capture_default_str();
  cmd->add_option("--probe-ms", b->probe_ms,
                  "Contention probe before and after the run: busy loops for this long on one "
                  "core, then on every core; with the hypervisor's steal time and the spread "
                  "between repeat blocks it decides whether the figures are trustworthy (a "
                  "warning and \"trustworthy\": false in the JSON when not); 0: no probe")
      ->capture_default_str();
  return [=]() -> int {
    b->warmup_given = warmup_option->count() > 0;
    b->repeats_given = repeats_option->count() > 0;
    b->refuse_one_device = o->devices == "auto";
    return study::run_bench_study(*o, *b, study::BenchHooks{}).exit_code;
  };
}

}  // namespace multiray::app
