#include "distributed/cluster.h"

#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>

#include <fmt/core.h>

#include "core/error.h"
#include "distributed/pixel_codec.h"

#ifdef MULTIRAY_HAS_MPI
#include "distributed/protocol.h"
#include "distributed/rank_worker.h"
#include "distributed/remote_device.h"
#include "distributed/scene_codec.h"
#include "distributed/transport.h"
#include "distributed/wire.h"
#endif

namespace multiray {

namespace {

// "R=DEVICES" → (R, DEVICES); throws InputError.
std::pair<int, std::string> parse_rank_devices(const std::string& text) {
  const auto eq = text.find('=');
  const auto bad = [&](const std::string& why) {
    return InputError("--rank-devices '" + text + "': " + why + " (expected R=DEVICES)");
  };
  if (eq == std::string::npos || eq == 0 || eq + 1 == text.size()) throw bad("not R=DEVICES");
  const std::string r = text.substr(0, eq);
  if (r.size() > 6 || r.find_first_not_of("0123456789") != std::string::npos)
    throw bad("'" + r + "' is not a rank number");
  return {std::stoi(r), text.substr(eq + 1)};
}

// --depth: "auto" (2, adapting) or a whole number in 1..64.
int parse_depth(const std::string& text) {
  if (text == "auto") return 2;
  if (text.empty() || text.size() > 2 ||
      text.find_first_not_of("0123456789") != std::string::npos || std::stoi(text) < 1 ||
      std::stoi(text) > 64)
    throw InputError("--depth '" + text + "' must be auto or a whole number in 1..64");
  return std::stoi(text);
}

// --result-encoding, checked: a name, an encoding this build can send, and never a lossy
// one beside the master's own unrounded pixels.
ResultEncoding parse_results(const DistributedOptions& o) {
  ResultEncoding e{};
  try {
    e = parse_result_encoding(o.result_encoding);
    remote::check_result_encoding(e);
  } catch (const std::invalid_argument& err) {
    throw InputError(std::string("--result-encoding ") + err.what());
  }
  if (is_lossy(e) && o.master_renders)
    throw InputError("--result-encoding " + o.result_encoding +
                     " rounds the workers' pixels, which --master-renders would mix with the "
                     "master's own: use float or float+zstd");
  return e;
}

}  // namespace

std::string Cluster::devices_of_this_rank(const std::string& all) const {
  std::string mine = all;
  for (const std::string& entry : options_.rank_devices) {
    const auto [r, devices] = parse_rank_devices(entry);
    if (r == rank()) mine = devices;
  }
  return mine;
}

#ifdef MULTIRAY_HAS_MPI

namespace {
// Testing aid (tests/mpi): MULTIRAY_TEST_KILL=R:F makes rank R kill itself when frame F
// starts there (a worker: when asked for it; the master: as it sends it), as a crashed
// machine would vanish. -1: not this rank.
int test_kill_frame(int rank) {
  int r = -1, f = -1;
  if (const char* kill = std::getenv("MULTIRAY_TEST_KILL"))
    if (std::sscanf(kill, "%d:%d", &r, &f) == 2 && r == rank) return f;
  return -1;
}

// --link, its error as bad input.
LinkSpec checked_link(const std::string& text) {
  try {
    return parse_link(text);
  } catch (const std::invalid_argument& e) {
    throw InputError(std::string("--link ") + e.what());
  }
}

}  // namespace

Cluster::Cluster(const DistributedOptions& o) : options_(o), link_(checked_link(o.link)) {
  if (!(o.worker_timeout_s >= 0.5 && o.worker_timeout_s <= 86400))
    throw InputError("--worker-timeout must be in [0.5, 86400] seconds");
  parse_depth(o.depth);
  parse_results(o);
  if (o.scene_from != "shared" && o.scene_from != "master")
    throw InputError("--scene-from '" + o.scene_from + "' must be shared or master");
  for (const std::string& entry : o.rank_devices) parse_rank_devices(entry);
  transport_ = std::make_shared<remote::Transport>(link_);
  if (size() < 2)
    throw InputError(
        "--distributed needs a master and at least one worker: run it as "
        "mpirun -np K multiray ... --distributed with K >= 2");
  for (const std::string& entry : o.rank_devices)
    if (const int r = parse_rank_devices(entry).first; r >= size())
      throw InputError(
          fmt::format("--rank-devices: rank {} does not exist (ranks 0..{})", r, size() - 1));
  // Both ways: the master tells a busy worker from a dead one, and a worker notices a
  // master that was killed (check_master_alive).
  transport_->set_heartbeat(std::chrono::milliseconds(250));
}

Cluster::~Cluster() {
  if (!transport_ || !master()) return;
  const auto quit = std::make_shared<const std::vector<uint8_t>>(
      remote::encode_quit(transport_->gave_up_on_anyone()));
  for (int r = 1; r < size(); ++r) transport_->send(r, remote::kQuit, quit);
}

int Cluster::rank() const { return transport_->rank(); }
int Cluster::size() const { return transport_->size(); }

void Cluster::send_scene(const Scene& scene) {
  const auto bytes = std::make_shared<const std::vector<uint8_t>>(remote::encode_scene(scene));
  for (int r = 1; r < size(); ++r) transport_->send(r, remote::kScene, bytes);
}

Scene Cluster::receive_scene() {
  for (;;) {
    std::optional<remote::Message> m =
        transport_->receive(0, remote::Transport::Clock::now() + std::chrono::seconds(1));
    check_master_alive(*transport_, options_.worker_timeout_s);
    if (!m) continue;
    if (m->tag == remote::kQuit) {  // the master could not start
      obey_quit(*transport_, *m);
      throw QuietExit{2};
    }
    if (m->tag == remote::kScene) {
      try {
        return remote::decode_scene(m->bytes);
      } catch (const remote::WireError& e) {
        throw InputError(std::string("the scene from the master: ") + e.what());
      }
    }
  }
}

void Cluster::say_hello(const std::vector<std::unique_ptr<Device>>& devices,
                        const PixelFingerprint& fingerprint) {
  remote::HelloMessage h;
  for (const auto& d : devices) h.devices.push_back(d->info());
  h.fingerprint = fingerprint;
  transport_->send(0, remote::kHello, remote::encode(h));
}

void Cluster::say_cannot_start(const std::string& why) {
  remote::HelloMessage h;
  h.ok = false;
  h.error = why;
  transport_->send(0, remote::kHello, remote::encode(h));
  // mpirun ends the whole job as soon as one rank exits with an error, which could cut the
  // master off before it printed why: wait until the master says quit (it does once it has).
  const auto until = remote::Transport::Clock::now() + std::chrono::seconds(30);
  while (remote::Transport::Clock::now() < until)
    if (auto m = transport_->receive(0, until); m && m->tag == remote::kQuit)
      return obey_quit(*transport_, *m);
}

std::vector<std::unique_ptr<Device>> Cluster::connect_workers(const PixelFingerprint& mine) {
  const auto timeout = std::chrono::milliseconds(int64_t(options_.worker_timeout_s * 1000));
  std::vector<std::optional<remote::HelloMessage>> hellos(static_cast<size_t>(size()));
  for (int waiting = size() - 1; waiting > 0;) {
    const auto now = remote::Transport::Clock::now();
    std::optional<remote::Message> m =
        transport_->receive(-1, now + std::chrono::milliseconds(100));
    if (!m) {
      for (int r = 1; r < size(); ++r)
        if (!hellos[size_t(r)] && now - transport_->last_heard(r) > timeout) {
          transport_->give_up(r);
          throw DeviceError(fmt::format("rank {} did not say it was ready within {} s", r,
                                        options_.worker_timeout_s));
        }
      continue;
    }
    if (m->tag != remote::kHello || m->from < 1 || hellos[size_t(m->from)]) continue;
    hellos[size_t(m->from)] = remote::decode_hello(m->bytes);
    --waiting;
    if (!hellos[size_t(m->from)]->ok)
      throw InputError(fmt::format("rank {}: {}", m->from, hellos[size_t(m->from)]->error));
    const std::string other = fingerprint_difference(mine, hellos[size_t(m->from)]->fingerprint);
    if (!other.empty())
      throw InputError(fmt::format("rank {} has another scene: {}", m->from, other));
  }
  std::vector<std::unique_ptr<Device>> devices;
  remote::RemoteOptions ro;
  ro.timeout = timeout;
  ro.depth = parse_depth(options_.depth);
  ro.auto_depth = options_.depth == "auto";
  ro.kill_at_frame = test_kill_frame(0);
  ro.results = parse_results(options_);
  for (int r = 1; r < size(); ++r)
    devices.push_back(
        std::make_unique<remote::RemoteDevice>(*transport_, r, *hellos[size_t(r)], ro));
  return devices;
}

int Cluster::serve(const std::vector<Device*>& devices, const RenderSettings& settings) {
  // mpirun forwards Ctrl-C and SIGTERM to every rank. The master finishes its frame and
  // writes its outputs (run/interrupt.h), which needs the workers' results: they carry on
  // until the master tells them to quit.
  std::signal(SIGINT, SIG_IGN);
  std::signal(SIGTERM, SIG_IGN);
  RankWorkerOptions wo;
  wo.balancer = options_.rank_balancer;
  wo.same_direction = options_.same_direction;
  wo.master_timeout_s = options_.worker_timeout_s;
  wo.kill_at_frame = test_kill_frame(rank());
  RankWorker worker(*transport_, devices, settings, wo);
  return worker.serve();
}

#else  // built without MPI

int Cluster::serve(const std::vector<Device*>&, const RenderSettings&) { return 0; }

Cluster::Cluster(const DistributedOptions& o) : options_(o) {
  throw InputError(
      "--distributed: this multiray was built without MPI (install "
      "libopenmpi-dev and openmpi-bin, and build with MULTIRAY_WITH_MPI=AUTO or ON)");
}
Cluster::~Cluster() = default;
int Cluster::rank() const { return 0; }
int Cluster::size() const { return 1; }
void Cluster::say_hello(const std::vector<std::unique_ptr<Device>>&, const PixelFingerprint&) {}
void Cluster::say_cannot_start(const std::string&) {}
std::vector<std::unique_ptr<Device>> Cluster::connect_workers(const PixelFingerprint&) {
  return {};
}
void Cluster::send_scene(const Scene&) {}
Scene Cluster::receive_scene() { return {}; }

#endif

}  // namespace multiray
