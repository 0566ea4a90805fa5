#include "app/help_groups.h"

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
       {"--out", "--overwrite", "--exr", "--exposure", "--tone", "--overlay", "--trace", "--quiet",
        "--json", "--report"}},
      {"Augmented reality", {"--ground", "--poses", "--background", "--ar"}},
      {"Benchmark", {"--warmup", "--ideal-frames", "--repeats", "--probe-ms"}},
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

}  // namespace multiray::app
