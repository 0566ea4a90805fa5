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

// The direction in which a balancer cuts a frame into contiguous parts, if it has one:
// `rows` gives each device horizontal bands (scanline ranges), `columns` vertical ones,
// `none` tiles, strips or a 2D tree. Harada's hierarchy (balance/hierarchy.h) reads it to
// make each level cut across the level above.
enum class CutAxis { none, rows, columns };

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

  // How plan() cuts the frame (see CutAxis). Fixed for the balancer's lifetime.
  virtual CutAxis cut_axis() const { return CutAxis::none; }
};

// Builds a balancer from a spec "name[:key=value]..." for `device_count` devices; the
// names, options, defaults and ranges are those of the registry (balance/registry.h,
// `multiray render --help`, docs/balancers.md). Throws std::invalid_argument with a
// one-line message for an unknown name or option, a malformed or out-of-range value, or
// device_count outside 1..4096.
std::unique_ptr<Balancer> make_balancer(const std::string& spec, int device_count);

// The names make_balancer accepts, in the registry's order: DESIGN.md's, then the peers'
// balancers, then any registered later.
std::vector<std::string> balancer_names();

}  // namespace multiray::balance
