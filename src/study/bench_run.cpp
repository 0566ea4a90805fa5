// `multiray bench`'s run (study/bench_run.h): every balancer on the same frames, in one
// process and interleaved frame by frame, with the ideal frame time measured by each
// device rendering sampled frames alone.
#include "study/bench_run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <optional>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "balance/balancer.h"
#include "core/console.h"
#include "core/error.h"
#include "core/file_io.h"
#include "core/machine_load.h"
#include "device/device_factory.h"
#include "engine/bench_harness.h"
#include "run/interrupt.h"
#include "run/start_run.h"
#include "study/bench_outputs.h"
#include "study/bench_repeats.h"
#include "study/bench_summary.h"
#include "study/report_plots.h"
#include "study/stats_json.h"
#include "util/spec.h"

namespace multiray::study {

std::string every_balancer() {
  // Not auto (it runs one of the others) nor subset (a baseline for --regret).
  std::string list;
  for (const std::string& name : balance::balancer_names())
    if (name != "auto" && name != "subset") list += (list.empty() ? "" : ",") + name;
  return list;
}

std::vector<std::string> regret_lanes(int device_count) {
  // The first lane of every frame runs ~1% slower on the same work (colder caches), so a
  // lane that is not compared goes first and last (odd blocks run in reverse order): all
  // devices without the participation rule (the default before it).
  std::vector<std::string> lanes = {"hybrid:bands=1:leave=0", "auto"};
  auto subset = [](unsigned mask) {
    std::string list;
    for (int d = 0; mask >> d; ++d)
      if (mask >> d & 1u) {
        if (!list.empty()) list += '+';
        list += std::to_string(d);
      }
    return "subset:devices=" + list;
  };
  if (device_count <= 4) {
    for (unsigned mask = 1; mask < (1u << device_count); ++mask) lanes.push_back(subset(mask));
  } else {
    for (int d = 0; d < device_count; ++d) lanes.push_back(subset(1u << d));
    lanes.push_back("subset:devices=all");
  }
  lanes.push_back("hybrid:bands=1:leave=0:probe=0");  // the same (probe is moot), last
  return lanes;
}

RunConfig bench_defaults() {
  RunConfig o;
  o.frames = 30;  // 11 balancers x 30 frames x 3 blocks: about a minute on two devices
  o.camera_path = "orbit";
  o.mesh_spp = 4;
  return o;
}

namespace {

// Block `block` of `repeats`: every lane over the run's frames into `out`, with progress and
// an ETA from `start` (the run's). Returns 0, or 128 + the signal that interrupted it (`out` then
// holds the frames every lane finished; the caller keeps them), or 130 when hooks.before_frame
// stopped it (the caller writes nothing).
int run_block(Session& session, const Run& s, const std::vector<double>& initial,
              const BenchConfig& config, int block, int repeats, const BenchHooks& hooks,
              BenchResult& out, std::string& signal_name,
              std::chrono::steady_clock::time_point start) {
  const bool terminal = stderr_is_tty(), progress = !hooks.quiet;
  std::optional<InterruptWatch> watch;
  if (!hooks.before_frame) watch.emplace(session);
  bool stopped = false;
  // The ETA from the run's pace since `start` (every block renders the same frames); off
  // a terminal, a line every 10 s.
  auto last_line = std::chrono::steady_clock::time_point{};
  out = run_bench(
      session, s.device_ptrs(), initial, s.perturbations, session.settings(), config, [&](int f) {
        const auto now = std::chrono::steady_clock::now();
        if (progress && (terminal || now - last_line > std::chrono::seconds(10))) {
          last_line = now;
          const double done = double(block) * config.frames + f;
          const double total = double(repeats) * config.frames;
          const double elapsed = std::chrono::duration<double>(now - start).count();
          const std::string eta =
              done > 0 ? fmt::format(", about {:.0f} s left", elapsed / done * (total - done))
                       : std::string();
          print_err("{}bench: block {}/{}  frame {}/{}{}{}", terminal ? "\r" : "", block + 1,
                    repeats, f + 1, config.frames, eta, terminal ? " \033[K" : "\n");
        }
        if (hooks.before_frame && !stopped && !hooks.before_frame()) {
          stopped = true;
          session.request_stop();
        }
      });
  if (progress && terminal) print_err("\r\033[K");
  if (stopped) return 130;
  if (!watch || !watch->signal()) return 0;
  signal_name = watch->signal_name();
  size_t done = out.lanes.empty() ? 0 : out.lanes[0].records.size();
  for (const BenchLane& lane : out.lanes) done = std::min(done, lane.records.size());
  if (!hooks.quiet)
    print_err(
        "multiray: bench interrupted by {} in block {} of {}, after {} of {} frames; keeping "
        "what finished (marked partial)\n",
        signal_name, block + 1, repeats, done, config.frames);
  return 128 + watch->signal();
}

// An interrupted first block: every lane cut to the frames all of them finished. Returns
// that count.
int cut_to_common_frames(BenchResult& r) {
  size_t n = r.lanes.empty() ? 0 : r.lanes[0].records.size();
  for (const BenchLane& lane : r.lanes) n = std::min(n, lane.records.size());
  for (BenchLane& lane : r.lanes) lane.records.resize(n);
  for (auto& frames : r.mismatched_frames)
    frames.erase(std::remove_if(frames.begin(), frames.end(), [n](int f) { return f >= int(n); }),
                 frames.end());
  r.ideal.erase(std::remove_if(r.ideal.begin(), r.ideal.end(),
                               [n](const IdealSample& i) { return i.frame >= int(n); }),
                r.ideal.end());
  return int(n);
}

BenchOutcome outcome(int code) {
  BenchOutcome out;
  out.exit_code = code;
  return out;
}

}  // namespace

BenchOutcome run_bench_study(RunConfig& o, BenchOptions& b, const BenchHooks& hooks) {
  if (b.repeats < 1 || b.repeats > 100) throw InputError("--repeats must be in 1..100");
  if (b.probe_ms < 0 || b.probe_ms > 10000) throw InputError("--probe-ms must be in 0..10000");
  // A distributed run's workers serve one session; repeating it is not built yet.
  if (o.distributed.enabled && b.repeats > 1) {
    if (b.repeats_given)
      throw InputError("--repeats above 1 does not work with --distributed yet");
    b.repeats = 1;
  }
  if (b.regret) {
    std::string list;
    for (const std::string& lane : regret_lanes(int(parse_device_specs(o.devices).size())))
      list += (list.empty() ? "" : ",") + lane;
    b.balancers = list;
  }
  if (b.lane_order != "rotate" && b.lane_order != "fixed")
    throw InputError("--lane-order must be rotate or fixed, not '" + b.lane_order + "'");
  const auto specs = split_spec_list(b.balancers);
  if (specs.empty()) throw InputError("--balancers is empty");
  check_frame_count(o.frames);  // before --warmup, whose range it sets
  const int warmup = b.warmup_given ? b.warmup : default_warmup(o.frames);
  if (warmup < 0 || warmup >= o.frames)
    throw InputError("--warmup must be in 0.." + std::to_string(o.frames - 1));
  if (b.ideal_frames < 1 || b.ideal_frames > 1000)
    throw InputError("--ideal-frames must be in 1..1000");
  if (!b.json_path.empty()) check_output_file(b.json_path, "--json");
  // Every lane's records stay in memory for the summaries (measured: ~1.2 KB a frame and
  // lane with two devices); --json adds their JSON (~12 KB more).
  const bool with_frames = !b.json_path.empty() || hooks.document;
  o.kept_bytes_per_frame = double(specs.size()) * (2048 + (with_frames ? 12288 : 0));
  Run s;
  int worker_exit = 0;
  std::vector<std::string> mapped = specs;  // --mapping applied by start_run
  std::unique_ptr<Session> session =
      start_run(s, o, mapped, "--balancers", &worker_exit, {}, {}, hooks.quiet);
  if (!session) return outcome(worker_exit);
  if (b.refuse_one_device && s.devices.size() == 1)
    throw InputError("bench compares balancers, and one device (" + s.devices[0]->info().spec +
                     ") has nothing to balance: give --devices several (`multiray devices` "
                     "lists this machine's; e.g. --devices "
                     "cpu:threads=1:cores=0,cpu:threads=1:cores=1)");
  for (const std::string& spec : mapped) report_auto_choice(s, spec, "--balancers", hooks.quiet);
  const std::vector<std::string> lanes = s.lane_labels(mapped);
  if (!b.report_dir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(b.report_dir, ec);
    if (ec)
      throw InputError("cannot create report folder '" + b.report_dir + "': " + ec.message());
  }
  std::vector<double> initial;
  std::vector<std::string> labels;
  for (size_t i = 0; i < s.devices.size(); ++i) {
    const DeviceInfo& info = s.devices[i]->info();
    initial.push_back(info.emulated_speed);
    labels.push_back(fmt::format("{}: {}", i, info.name));
  }
  if (!hooks.quiet) print_run_header(s, o, labels);

  BenchConfig config;
  config.frames = o.frames;
  config.warmup = warmup;
  config.ideal_frames = b.ideal_frames;
  config.partition_frame = b.report_dir.empty() ? -1 : o.frames / 2;
  config.keep_stats = !b.trace_prefix.empty();
  config.reference_step = s.volume ? o.volume.reference_step : 0;
  // Block 0 gives the per-frame outputs (table, JSON frames, plots, traces); every block
  // adds its per-frame figures to the repeat statistics.
  BenchResult result;
  std::vector<RepeatLane> repeat_lanes;
  const int perturb_frame = s.perturbations.empty() ? -1 : s.perturbations.front().frame;
  balance::NoiseReadings noise;
  noise.probe_before = b.probe_ms > 0 ? contention_probe(b.probe_ms) : NAN;
  const CpuTimes cpu_before = read_cpu_times();
  const auto started = std::chrono::steady_clock::now();
  const int repeats_asked = b.repeats;
  int interrupted = 0, blocks_done = b.repeats;
  std::string signal;  // the signal's name when one interrupted the run
  for (int block = 0; block < b.repeats; ++block) {
    // --regret: odd blocks run the lanes in reverse order. A lane's frame time depends by
    // ~0.5% on the lane rendered before it (which caches and cores it left warm), which is
    // the size of the differences the regret is about.
    const bool reversed = b.regret && block % 2 == 1;
    std::vector<std::string> order = mapped;
    if (reversed) std::reverse(order.begin(), order.end());
    if (block > 0) session = s.make_session(order, "--balancers");
    session->set_rotate_lanes(b.lane_order == "rotate" && !b.regret, size_t(block));
    BenchResult r;
    const int code =
        run_block(*session, s, initial, config, block, b.repeats, hooks, r, signal, started);
    if (code == 130 && signal.empty()) {  // hooks.before_frame: the caller wants nothing
      BenchOutcome stopped = outcome(code);
      stopped.interrupted = true;
      return stopped;
    }
    if (code) {
      // Interrupted: the blocks that finished stand; a first block is cut to the frames
      // every lane finished, and kept if some follow the warm-up.
      interrupted = code;
      blocks_done = block;
      if (block > 0) break;
      const int n = cut_to_common_frames(r);
      if (n <= warmup) {
        if (!hooks.quiet)
          print_err("multiray: no frame after the warm-up ({}) had finished: nothing to keep\n",
                    warmup);
        BenchOutcome stopped = outcome(code);
        stopped.interrupted = true;
        return stopped;
      }
      o.frames = config.frames = n;
      config.partition_frame = -1;
      blocks_done = 1;
    }
    if (reversed) {  // back in the lanes' order
      std::reverse(r.lanes.begin(), r.lanes.end());
      std::reverse(r.mismatched_frames.begin(), r.mismatched_frames.end());
    }
    add_block(repeat_lanes, lanes, r, warmup, perturb_frame);
    if (block == 0) result = std::move(r);
    if (interrupted) break;
  }
  b.repeats = blocks_done;  // what the statistics below are over
  noise.steal = steal_fraction(cpu_before, read_cpu_times());
  noise.probe_after = b.probe_ms > 0 ? contention_probe(b.probe_ms) : NAN;
  for (const BenchLane& lane : result.lanes)
    for (const FrameRecord& rec : lane.records)
      for (const auto& m : rec.messages)
        if (!hooks.quiet) print_err("multiray: warning: {}\n", m);
  nlohmann::json ideal_detail = nlohmann::json::array();
  for (const IdealSample& i : result.ideal) {
    ideal_detail.push_back(
        {{"frame", i.frame}, {"device_alone_ms", i.device_alone_ms}, {"ideal_ms", i.ideal_ms}});
  }
  // The ideal efficiency compares against: each frame's, interpolated between the timed
  // ones, averaged over the summarised frames.
  const double ideal_mean = mean_ideal_ms(result.ideal, warmup, o.frames);
  if (!hooks.quiet)
    print_out(
        "ideal frame time {:.1f} ms (mean over frames {}-{}, interpolated between {} frames "
        "on which each device was timed alone)\n",
        ideal_mean, warmup, o.frames - 1, result.ideal.size());

  std::vector<RunSummary> summaries;
  for (const BenchLane& lane : result.lanes)
    summaries.push_back(summarize(lane.records, warmup, result.ideal, perturb_frame));
  add_speedups(lanes, summaries);
  if (!hooks.quiet && b.repeats > 1)
    print_out(
        "block 1 of {} (its frames give the table below, the plots and the JSON "
        "frames; the repeat statistics follow):\n",
        b.repeats);
  if (!hooks.quiet) {
    print_table(lanes, summaries, perturb_frame >= 0);
    print_breakdown(lanes, summaries);
  }
  // Bit-identical images are promised per device type; with several types the split
  // decides which pixels carry which type's last-bit rounding, so hashes are not compared.
  bool mixed_types = false;
  for (const auto& d : s.devices) mixed_types |= d->info().type != s.devices[0]->info().type;
  if (!hooks.quiet && mixed_types)
    print_out(
        "(mixed device types: images agree statistically, not bit for bit, so they are "
        "not compared)\n");
  // Every view of every frame, between the lanes that rendered it at the same quality.
  const std::string mismatch =
      mixed_types ? "" : mismatch_summary(lanes, result.mismatched_frames);
  if (!hooks.quiet && !mixed_types && mismatch.empty())
    print_out(
        "(images: every view of every frame bit-identical across the balancers that "
        "rendered it at the same quality)\n");
  const TimelineScale timeline =
      timeline_scale(result, warmup, result.lanes.empty() ? 0 : result.lanes[0].records.size());
  nlohmann::json runs_json = nlohmann::json::array();
  std::vector<uint32_t> reference_views;  // reprojected sampling's, the same every frame
  for (int v : s.views->rig().reference_views(s.views->sampling().reference_spacing))
    reference_views.push_back(uint32_t(v));
  std::vector<std::string> names;
  for (size_t k = 0; k < result.lanes.size(); ++k)
    names.push_back(session->engine(k).balancer().name());
  const std::vector<std::string> stems = lane_file_stems(names);
  for (size_t k = 0; k < result.lanes.size(); ++k)
    runs_json.push_back(lane_outputs(k, s, result, lanes, labels, summaries[k], reference_views,
                                     mixed_types, timeline, warmup, config.partition_frame, b,
                                     with_frames, stems[k]));
  if (s.volume) report_volume(s, result, lanes, labels, warmup, b.report_dir, hooks.quiet);
  const RepeatSummary repeats = summarize_repeats(repeat_lanes, perturb_frame >= 0);
  if (!b.report_dir.empty())
    write_comparison_svg(
        b.report_dir + "/comparison.svg",
        fmt::format("balancers compared — {} ({}x{}, frames {}-{}, {})", s.scene->name,
                    s.res.width, s.res.height, warmup, o.frames - 1,
                    b.repeats > 1 ? fmt::format("medians of {} blocks, 95% intervals", b.repeats)
                                  : std::string("means of one block")),
        comparison_bars(repeats, summaries));
  bool emulated = false;
  for (double v : initial) emulated |= v < 1;
  if (!hooks.quiet && (emulated || !s.perturbations.empty()))
    print_out("(device speeds below 1 are emulated: the device idles after each piece of work)\n");
  if (!hooks.quiet && b.repeats > 1) print_repeats(repeats);
  const nlohmann::json regret = b.regret ? regret_of(repeat_lanes, repeats) : nlohmann::json();
  if (!hooks.quiet && b.regret) print_out("{}\n", regret["text"].get<std::string>());
  const balance::NoiseVerdict verdict = judge_noise(noise, repeat_lanes);
  if (!hooks.quiet) print_noise(noise, verdict);
  BenchOutcome out;
  if (with_frames) {
    nlohmann::json& doc = out.doc;
    doc = run_description(s, o);
    doc["repeats"] = repeats_to_json(repeats);
    if (b.regret) doc["regret"] = regret;
    doc["trustworthy"] = verdict.trustworthy;
    doc["noise"] = noise_to_json(noise, verdict);
    doc["ideal_ms"] = ideal_mean;
    doc["ideal"] = ideal_detail;
    doc["images_identical"] = mixed_types ? nlohmann::json("not compared: mixed device types")
                                          : nlohmann::json(mismatch.empty());
    doc["runs"] = std::move(runs_json);
    if (interrupted)
      doc["partial"] = {{"interrupted_by", signal},
                        {"frames", o.frames},
                        {"blocks", blocks_done},
                        {"blocks_asked", repeats_asked}};
    doc["image_reference"] =
        o.volume.reference_step > 0
            ? fmt::format("every frame at step {} voxel lengths", o.volume.reference_step)
            : std::string("the first lane's full-quality frames");
    if (!b.json_path.empty()) write_file_atomically(b.json_path, dump_json(doc) + "\n");
  }
  out.mismatch = mismatch;
  if (interrupted) {
    out.exit_code = interrupted;
    if (!hooks.quiet)
      print_err("multiray: partial: {} block{} of {}, frames 0-{} (interrupted by {})\n",
                blocks_done, blocks_done == 1 ? "" : "s", repeats_asked, o.frames - 1, signal);
    return out;
  }
  if (!mismatch.empty()) {
    // A broken promise of the renderer: reported after the table and JSON, exit code 1.
    out.exit_code = 1;
    if (!hooks.quiet)
      print_err(
          "multiray: error: images differ between balancers rendering at the same "
          "quality (every view of every frame compared; mismatched_frames in the JSON): "
          "{}\n",
          mismatch);
  }
  return out;
}

}  // namespace multiray::study
