// `--distributed`: one mpirun job, rank 0 the master, the other ranks workers (Seo et al.
// 2022 §4; Harada, GPU Pro 7 Fig. 4.5). Every rank parses the same command line and loads
// the scene from the same path; the master plans, composites and writes, and sees each
// worker as one device (distributed/remote_device.h); each worker renders what it is
// sent over its own local devices (distributed/rank_worker.h). Built only with MPI
// (MULTIRAY_WITH_MPI); without it --distributed is refused with one line.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "device/device.h"
#include "distributed/fingerprint.h"
#include "distributed/link.h"
#include "distributed/options.h"
#include "scene/scene.h"

namespace multiray::remote {
class Transport;
}

namespace multiray {

// A worker printing nothing and ending with this exit code (the master reports why).
struct QuietExit {
  int code = 2;
};

// This process's place in a distributed run. Creating it starts MPI.
class Cluster {
 public:
  // Checks the options and starts MPI; throws InputError for bad options, fewer than two
  // ranks, or a build without MPI.
  explicit Cluster(const DistributedOptions& o);
  // The master tells every worker still answering to quit.
  ~Cluster();
  int rank() const;
  int size() const;
  bool master() const { return rank() == 0; }
  const DistributedOptions& options() const { return options_; }
  const remote::LinkSpec& link() const { return link_; }
  remote::Transport& transport() { return *transport_; }
  // The --devices of this rank: its --rank-devices entry, else `all`.
  std::string devices_of_this_rank(const std::string& all) const;

  // --scene-from master. Master: sends the loaded scene (lighting applied) to every
  // worker. Worker: waits for it; throws QuietExit when the master quits first.
  void send_scene(const Scene& scene);
  Scene receive_scene();
  // Worker: tells the master it is ready with `devices` and what decides its pixels, or
  // why it cannot start.
  void say_hello(const std::vector<std::unique_ptr<Device>>& devices,
                 const PixelFingerprint& fingerprint);
  // (This one returns once the master said quit, at most 30 s later.)
  void say_cannot_start(const std::string& why);
  // Master: waits for every worker's hello and returns one device per worker. Throws
  // InputError naming the first worker that cannot start or whose fingerprint is not
  // `mine` ("rank 2 has another scene: 'a.obj' differs (...)"), DeviceError for a
  // silent one.
  std::vector<std::unique_ptr<Device>> connect_workers(const PixelFingerprint& mine);
  // Worker: serves the master over `devices` with `settings` (the master sends each
  // frame's changes) until it says quit; returns the exit code.
  int serve(const std::vector<Device*>& devices, const RenderSettings& settings);

 private:
  DistributedOptions options_;
  remote::LinkSpec link_;
  std::shared_ptr<remote::Transport> transport_;  // (shared_ptr: no MPI type needed here)
};

}  // namespace multiray
