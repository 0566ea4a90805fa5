// The balancer interface: pure policy over plain structs. A balancer is asked for a Plan
// before each frame and told the measured FrameStats after it; it owns no threads and
// touches no device, so it can be unit-tested with simulate() and linked by any renderer.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "balance/plan.h"
#include "balance/stats.h"

namespace multiray::balance {

class Balancer {
 public:
  virtual ~Balancer() = default;

  // Short name, as in the spec ("hybrid").
  virtual std::string name() const = 0;
  // The spec with every parameter spelled out
  // ("dlb:interval=5:band=0.1:slow=0.75:bits=auto:strip=32"), for logs and benchmark records;
  // make_balancer(spec()) builds an equivalent balancer.
  virtual std::string spec() const { return name(); }

  // The plan for `frame` of `shape`. Throws std::invalid_argument for an invalid shape
  // (see validate_shape). Devices that were dropped get an empty list and ratio 0; if no
  // device is left every list is empty and all ratios are 0.
  virtual Plan plan(const FrameShape& shape, int frame) = 0;

  // Feeds back what the devices measured for the frame last planned. Tolerates garbage:
  // times of 0, negative, NaN or infinite, devices that did no work, missing devices,
  // reports of a different shape. Such measurements are ignored (previous ratios are
  // kept); they never produce NaN ratios. A device reported `alive = false` is dropped.
  virtual void update(const FrameStats& stats) = 0;

  // Device `index` died: later plans give it nothing. Out-of-range indices are ignored.
  virtual void drop_device(int index) = 0;
};

// Builds a balancer from a spec "name[:key=value]..." for `device_count` devices:
//   uniform[:layout=rows|columns|strips|views]
//   static[:ratios=3/1][:layout=...]      (no ratios: calibrate from the first frame)
//   queue[:tile=64][:batch=1]
//   semi-static[:alpha=0.4]
//   dlb[:interval=5][:band=0.1][:slow=0.75][:bits=auto][:strip=32][:layout=strips|views]
//   hybrid[:bands=8][:taper=0.7][:tail=0.02][:alpha=0.5][:jump=0.2][:gamma=0.5]
//         [:min_chunk=256][:steal=1][:overhead=0.1]
//   bruder[:zeta=0.5][:tile=8][:steal=0][:items=rows]  (Bruder et al. 2017: predicted costs,
//                                                 k-d tree of tiles)
// and, to compare against the peers (peers_*.h):
//   cycles[:interval_ms=1000]                    (Blender Cycles)
//   equalizer[:damping=0.5]                      (Equalizer's load equalizer, 2D)
//   ospray-static[:tile=64]                      (OSPRay MPI, round-robin tiles)
//   ospray-dynamic[:tile=64][:prefetch=4]        (OSPRay MPI, tiles on request)
// docs/balancers.md explains each parameter. Throws std::invalid_argument with a one-line
// message for an unknown name or option, a malformed or out-of-range value, or
// device_count outside 1..4096.
std::unique_ptr<Balancer> make_balancer(const std::string& spec, int device_count);

// The names make_balancer accepts, in the order of DESIGN.md, then the peers' balancers.
std::vector<std::string> balancer_names();

}  // namespace multiray::balance
