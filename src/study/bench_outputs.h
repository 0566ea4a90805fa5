// What `multiray bench` reports beside its tables (study/bench_run.h runs it): the header
// lines, each lane's JSON entry with its trace and plots, the volume set-up and targeting
// reports, and the description of the run at the top of the JSON.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/bench_harness.h"
#include "run/run.h"
#include "study/bench_run.h"
#include "study/bench_summary.h"
#include "study/report_plots.h"

namespace multiray::study {

// The line saying what is benchmarked, and one line per device.
void print_run_header(const Run& s, const RunConfig& o, const std::vector<std::string>& labels);

// One lane's JSON entry (its frames and summary), and its trace and plots when asked for.
// The per-frame JSON (several KB a frame) is made only `with_frames` (--json, Python).
nlohmann::json lane_outputs(size_t k, const Run& s, const BenchResult& result,
                            const std::vector<std::string>& lanes,
                            const std::vector<std::string>& labels, const RunSummary& summary,
                            const std::vector<uint32_t>& reference_views, bool mixed_types,
                            const TimelineScale& timeline, int warmup, int partition_frame,
                            const BenchOptions& b, bool with_frames, std::string name);

// Volumes: the set-up times (printed unless `quiet`), and with --target-ms the targeting
// table (likewise) and plots (in `report_dir`, when given).
void report_volume(const Run& s, const BenchResult& result, const std::vector<std::string>& lanes,
                   const std::vector<std::string>& labels, int warmup,
                   const std::string& report_dir, bool quiet);

// What the bench ran, for its JSON: scene, image, sampling, frames, camera path, and how
// time was measured (the measurements are added beside it).
nlohmann::json run_description(const Run& s, const RunConfig& o);

}  // namespace multiray::study
