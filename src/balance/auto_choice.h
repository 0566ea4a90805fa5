// `--balancer auto`: which balancer to run, chosen from the devices, the link and the
// workload. The choice is a pure function over plain data (choose_balancer), so the rule
// table in auto_choice.cpp can be re-measured and edited without touching the run layer;
// docs/balancers.md ("auto") states the same table.
//
// Built without context (make_balancer("auto", n): a library user, the viewer's switcher)
// only the device count is known: AutoBalancer runs the choice for n devices of unknown
// type. The run layer (run/run.h) knows the devices and resolves `auto` itself.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "balance/balancer.h"

namespace multiray::balance {

// One device the run renders on, as the rules see it: plain data, filled by the run layer
// from the device backend registry (device/device_factory.h), so no rule names a backend.
struct AutoDevice {
  std::string type;    // a name for the reason line ("cpu", "remote", ...); empty: unknown
  int threads = 1;     // hardware threads it renders with (a rank: over its devices)
  double speed = 1.0;  // emulated speed, (0, 1]; 1: not emulated
  // It pays a fixed cost per item, such as a kernel launch (BackendFeatures::item_cost);
  // a worker rank: one of its own devices does.
  bool item_cost = false;
};

struct AutoInputs {
  std::vector<AutoDevice> devices;   // the devices the top-level balancer splits between
  bool distributed = false;          // --distributed: devices are worker ranks
  int ranks = 0;                     // MPI ranks, master included (0: not distributed)
  double latency_ms = 0;             // the link's one-way latency; 0: none known
  double mbit_per_s = 0;             // the link's bandwidth; 0: none known (or unlimited)
  bool volume = false;               // a volume (else a mesh)
  int views = 1;                     // views per frame (light-field grid, stereo pair)
  std::string sampling = "uniform";  // uniform | adaptive | foveated | reproject
  bool frame_target = false;         // a frame-time target is set (volumes)
  bool catcher = false;              // a shadow catcher (--ground): augmented reality
};

struct AutoChoice {
  std::string spec;    // a concrete balancer spec, never "auto"
  std::string reason;  // one line: what was seen and why this balancer, for stderr/stats
};

// The first row of the rule table (auto_choice.cpp) that applies. Never throws.
AutoChoice choose_balancer(const AutoInputs& in);

// What make_balancer("auto", n) builds: choose_balancer for n devices of unknown type,
// under the name "auto" (so its spec round-trips); every call goes to the chosen one.
class AutoBalancer : public Balancer {
 public:
  explicit AutoBalancer(int device_count);
  std::string name() const override { return "auto"; }
  const AutoChoice& choice() const { return choice_; }
  Plan plan(const FrameShape& shape, int frame) override { return chosen_->plan(shape, frame); }
  void update(const FrameStats& stats) override { chosen_->update(stats); }
  void drop_device(int index) override { chosen_->drop_device(index); }
  CutAxis cut_axis() const override { return chosen_->cut_axis(); }

 private:
  AutoChoice choice_;
  std::unique_ptr<Balancer> chosen_;
};

}  // namespace multiray::balance
