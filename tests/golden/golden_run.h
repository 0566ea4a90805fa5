// Rendering a golden case through the command line, as a user would, and collecting what
// it wrote: every frame's hash from stats.json and every view's linear EXR image.
#pragma once

#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/image.h"
#include "golden/cases.h"
#include "support/run_cli.h"

namespace multiray::testing {

struct CaseRender {
  CliResult cli;
  std::vector<std::string> hashes;            // per frame
  std::map<std::string, Framebuffer> images;  // by file stem: frame_0000, frame_0001_view02
};

// The scene argument of `c`: empty for the built-in scene, else the file under `data_dir`.
inline std::string golden_scene(const GoldenCase& c, const std::string& data_dir) {
  return c.scene.empty() ? "" : data_dir + "/" + c.scene;
}

// Renders `c` with `extra` options (devices, balancer, seed) into `dir` (replaced), with
// `env` (shell assignments) in front of the command.
inline CaseRender render_golden_case(const std::string& binary, const GoldenCase& c,
                                     const std::string& data_dir, const std::string& extra,
                                     const std::string& dir, const std::string& env = "") {
  std::filesystem::remove_all(dir);
  CaseRender r;
  r.cli = run_cli(binary,
                  "render -q " + golden_scene(c, data_dir) + " " + c.args + " " + extra +
                      " --exr --out " + dir,
                  env);
  if (r.cli.code != 0) return r;
  std::ifstream in(dir + "/stats.json");
  if (!in) return r;
  const nlohmann::json stats = nlohmann::json::parse(in);
  for (const auto& f : stats.at("frames"))
    r.hashes.push_back(f.at("image_hash").get<std::string>());
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.path().extension() == ".exr")
      r.images[e.path().stem().string()] = read_exr(e.path().string());
  return r;
}

}  // namespace multiray::testing
