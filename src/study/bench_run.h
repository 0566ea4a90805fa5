// The work of `multiray bench`: the run built, every balancer over the same frames in
// repeat blocks, the summaries, plots and traces, and the --json document. The CLI
// (app/bench_command.cpp) declares the options and prints as it goes; the Python module's
// bench() (src/python/studies.cpp) runs it quietly and returns the document.
#pragma once

#include <functional>
#include <string>

#include <nlohmann/json.hpp>

#include "run/run_config.h"

namespace multiray::study {

// Every registered balancer, "uniform,static,...", but `auto` (it runs one of the others:
// a second lane of the same balancer).
std::string every_balancer();

// The options bench adds to render's (RunConfig), named as the CLI's.
struct BenchOptions {
  std::string balancers = every_balancer();
  std::string json_path;
  std::string report_dir;
  std::string trace_prefix;
  int warmup = 0;  // used when warmup_given; default_warmup(frames) otherwise
  bool warmup_given = false;
  int ideal_frames = 20;
  int repeats = 3;
  bool repeats_given = false;  // --repeats given (refused above 1 with --distributed)
  int probe_ms = 200;
  // --regret: the default (`auto`) against every subset of the devices (each alone, all
  // together without the participation rule: `subset` lanes) instead of --balancers.
  bool regret = false;
  // --lane-order: "rotate" starts frame f at lane f mod L (Session::set_rotate_lanes);
  // "fixed" renders the lanes in the order given, as every bench before 2026-12-04 did.
  // --regret keeps its own order (regret_lanes).
  std::string lane_order = "rotate";
  // One device after --devices is resolved (the command line's default, auto, on a
  // machine with nothing but its cores) is refused in one line: nothing to compare.
  bool refuse_one_device = false;
};

// The lanes of --regret for `device_count` devices: a first lane not compared (the first
// lane of a frame runs on colder caches), "auto", then `subset` of each non-empty subset
// (every device alone, pairs, ..., all), at most 4 devices (more: each alone and all).
// The regret is auto's frame time over the best subset's.
std::vector<std::string> regret_lanes(int device_count);

// A RunConfig with bench's defaults: 30 frames, the orbit camera path, 4 spp for meshes.
RunConfig bench_defaults();

struct BenchHooks {
  // No lines on stdout or stderr (header, progress, tables, notes, warnings): the caller
  // has the document.
  bool quiet = false;
  // Build the whole document (every frame's record) even without --json.
  bool document = false;
  // Called before every frame renders (on the thread that called run_bench_study); false
  // stops the run there (the outcome is then interrupted, with no output). Empty:
  // SIGINT/SIGTERM stop it (run/interrupt.h).
  std::function<bool()> before_frame;
};

struct BenchOutcome {
  // 0; 1 when images differ between balancers at the same quality (`mismatch` says
  // where; the document is complete); 128 + the signal that stopped the run, or 130 when
  // before_frame did; a distributed worker's exit code.
  // A signal keeps what finished: the blocks done, or the frames of the first block that
  // every lane finished (if some follow the warm-up), reported and written with "partial"
  // in the document; exit_code is then 128 + the signal and `interrupted` stays false.
  int exit_code = 0;
  bool interrupted = false;  // stopped with nothing kept (before_frame, or too early)
  nlohmann::json doc;        // the --json document (null when interrupted or on a worker)
  std::string mismatch;      // mismatch_summary(); empty when every image agreed
};

// Runs bench with `o` and `b` (InputError with the CLI's one-line message for bad input,
// before anything renders); writes --json, --report and --trace files when asked for.
BenchOutcome run_bench_study(RunConfig& o, BenchOptions& b, const BenchHooks& hooks);

}  // namespace multiray::study
