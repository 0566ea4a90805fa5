#include "app/help_groups.h"

#include "balance/registry.h"

#include <algorithm>
#include <utility>
#include <vector>

namespace multiray::app {

namespace {

// Sections in the order --help shows them, each with its options.
const std::vector<std::pair<std::string, std::vector<std::string>>>& groups() {
  static const std::vector<std::pair<std::string, std::vector<std::string>>> table = {
      {"Scene", {"--env", "--env-scale", "--sun", "--up", "--allow-outside-paths", "--raw"}},
      {"Camera and animation",
       {"--camera", "--camera-path", "--frames", "--sequence", "--views", "--view-spacing",
        "--stereo"}},
      {"Sampling",
       {"--res", "--spp", "--clamp", "--bounces", "--seed", "--integrator", "--depth", "--ao-rays",
        "--ao-distance", "--sampling", "--edge-spp", "--reference-spacing", "--gaze",
        "--gaze-path", "--fovea-spp", "--fovea-radius", "--periphery-spp"}},
      {"Devices and balancing",
       {"--devices", "--threads", "--balancer", "--balancers", "--regret", "--mapping",
        "--perturb", "--max-memory"}},
      {"Volumes",
       {"--tf", "--step", "--target-ms", "--adapt", "--adapt-space", "--prepass-stride",
        "--cost-model", "--reference-step"}},
      {"Output",
       {"--out", "--overwrite", "--exr", "--aov", "--denoise", "--denoise-normal",
        "--svgf-history", "--no-denoise-overlap", "--exposure", "--tone", "--overlay", "--trace",
        "--quiet", "--json", "--report"}},
      {"Augmented reality", {"--ground", "--poses", "--background", "--ar"}},
      {"Benchmark", {"--warmup", "--ideal-frames", "--repeats", "--lane-order", "--probe-ms"}},
      {"Viewer",
       {"--port", "--bind", "--max-clients", "--max-frames", "--frame-spp", "--move-scale"}},
      {"Several machines (MPI)",
       {"--distributed", "--rank-devices", "--master-renders", "--rank-balancer",
        "--rank-same-direction", "--link", "--scene-from", "--result-encoding",
        "--worker-timeout"}},
  };
  return table;
}

}  // namespace

std::string help_group(const std::string& option_name) {
  for (const auto& [group, options] : groups())
    for (const std::string& o : options)
      if (o == option_name) return group;
  return "";
}

void group_options(CLI::App& cmd) {
  // CLI11 prints the sections in the order their first options were added, and each
  // section's options in the order they were added.
  for (CLI::Option* opt : cmd.get_options()) {
    const std::string& name = opt->get_lnames().empty() ? "" : opt->get_lnames().front();
    const std::string group = help_group("--" + name);
    if (!group.empty()) opt->group(group);
  }
}

void hide_uncommon_options(CLI::App& cmd) {
  // What a first run and most later ones use; the rest is one flag away.
  static const std::vector<std::string> common = {
      "--res",     "--spp",        "--frames",    "--camera",   "--camera-path",
      "--env",     "--devices",    "--threads",   "--balancer", "--balancers",
      "--regret",  "--out",        "--overwrite", "--exr",      "--exposure",
      "--overlay", "--quiet",      "--json",      "--report",   "--repeats",
      "--trace",   "--integrator", "--port",      "--bind",     "--denoise"};
  // The two long entries, shortened (their full lists are in --help-all).
  if (CLI::Option* d = cmd.get_option_no_throw("--devices"))
    d->description(
        "auto (every core as one cpu device and each GPU OpenCL offers) or a comma-separated "
        "list, e.g. cpu:threads=1:cores=0,opencl:0 (`multiray devices` lists this machine's "
        "and every key)");
  std::string names;  // from the registry, so the list cannot go stale
  for (const balance::BalancerEntry& e : balance::balancer_registry()) {
    if (!names.empty()) names += ", ";
    names += e.name;
  }
  for (const char* name : {"--balancer", "--balancers"})
    if (CLI::Option* b = cmd.get_option_no_throw(name))
      b->description("How work is split between devices, NAME[:key=value]...: " + names +
                     " (docs/balancers.md; --help-all lists every key)");
  size_t hidden = 0;
  for (CLI::Option* opt : cmd.get_options()) {
    if (opt->get_lnames().empty() || opt->get_lnames().front() == "help") continue;
    const std::string name = "--" + opt->get_lnames().front();
    if (std::find(common.begin(), common.end(), name) != common.end()) continue;
    opt->group("");
    ++hidden;
  }
  if (hidden > 0)
    cmd.footer(std::to_string(hidden) +
               " more options (scene and lights, sampling, volumes, multiview, augmented "
               "reality, several machines, benchmarks, the viewer): multiray " +
               cmd.get_name() + " --help-all");
}

}  // namespace multiray::app
