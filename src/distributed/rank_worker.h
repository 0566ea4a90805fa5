// A worker rank of a distributed run (`--distributed`, ranks >= 1): it serves the master's
// requests (distributed/protocol.h) over its own local devices until told to quit.
// Every item the master sends is one region to balance across the local devices, with
// the worker's own balancer (RegionBalancer over --rank-balancer): Harada's hierarchy,
// where the master splits the frame into bands across machines and each machine splits
// its band across its devices in the other direction (GPU Pro 7, Fig. 4.5). With one
// local device the region simply goes to it.
//
// Results go back as soon as an item is done (the transport sends them while the next
// item renders), after a Ready report when the Work message asks for one (Seo et al.
// 2022, strategy I: protocol.h), or, for a batched Work message, all in one message after
// its last item (strategy II).
#pragma once

#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "balance/region.h"
#include "distributed/protocol.h"
#include "distributed/transport.h"
#include "engine/engine.h"

namespace multiray {

struct RankWorkerOptions {
  std::string balancer = "semi-static";  // the local split of each region
  bool same_direction = false;           // split along the master's bands, not across (Harada)
  int kill_at_frame = -1;                // testing aid: SIGKILL itself when asked for it
  double master_timeout_s = 10;          // silence of the master that ends the worker
};

// Throws DeviceError when nothing (not even a heartbeat: the master's transport sends one
// every 250 ms) has come from the master for `timeout_s`: it was killed or its machine
// is gone, and without this the worker would wait forever. MPI is then not finalised
// (MPI_Finalize would wait for the dead master).
void check_master_alive(remote::Transport& transport, double timeout_s);

// Ends this worker's part in MPI as the master's Quit says: when the master gave up on
// a rank (or the message does not parse), MPI must not be finalised here, since
// MPI_Finalize would wait for that rank forever (transport.h).
void obey_quit(remote::Transport& transport, const remote::Message& quit);

class RankWorker {
 public:
  // `local` must outlive the worker. `base` gives what the master does not send (the
  // volume style).
  RankWorker(remote::Transport& transport, std::vector<Device*> local, RenderSettings base,
             RankWorkerOptions options);

  // Serves until the master says Quit; returns 0. Faults of the local devices go back to
  // the master as Failure messages; nothing here throws for them. Throws DeviceError when
  // the master falls silent (check_master_alive).
  int serve();

 private:
  void start_frame(const remote::FrameMessage& m);
  void render_work(const remote::WorkMessage& m);
  remote::ItemResult render_item(uint32_t id, const WorkItem& item);
  void fail(const std::string& why);

  remote::Transport& transport_;
  std::vector<Device*> local_;
  RenderSettings base_, settings_;
  RankWorkerOptions options_;
  balance::RegionBalancer* region_ = nullptr;             // owned by engine_
  balance::CutAxis inner_axis_ = balance::CutAxis::none;  // the local balancer's own
  std::unique_ptr<Engine> engine_;
  std::vector<ViewSetup> views_;
  std::vector<std::vector<uint8_t>> spp_maps_;
  std::vector<Framebuffer> images_;
  std::vector<remote::LocalDeviceTime> times_;  // per local device, this frame so far
  uint32_t epoch_ = 0;
  ResultEncoding results_ = ResultEncoding::float32;  // this frame's, from the master
  bool failed_ = false;                               // this frame: every local device failed
  // Waiting for the next item after finishing one, this frame (ms), and since when.
  double idle_ms_ = 0;
  std::optional<std::chrono::steady_clock::time_point> idle_since_;
  int passes_ = 0;  // local engine frames so far (the local balancer's frame count)
};

}  // namespace multiray
