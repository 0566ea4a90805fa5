// What --distributed asks for, as plain data (a part of run/run_config.h's RunConfig).
#pragma once

#include <string>
#include <vector>

namespace multiray {

// --distributed and its options (distributed/cluster.h).
struct DistributedOptions {
  bool enabled = false;
  std::vector<std::string> rank_devices;  // "R=DEVICES": rank R's --devices
  bool master_renders = false;            // rank 0 also renders with --devices
  std::string rank_balancer = "semi-static";
  bool same_direction = false;  // workers split their part along the master's axis
  std::string link = "none";
  double worker_timeout_s = 10;
  std::string depth = "auto";         // auto (adapts, from 2) or a fixed depth
  std::string scene_from = "shared";  // shared: every rank loads it; master: sent to workers
  // How workers send pixels back (util/result_encoding.h); the master's choice is sent to
  // every worker with each frame. Lossless by default.
  std::string result_encoding = "float+zstd";
};

}  // namespace multiray
