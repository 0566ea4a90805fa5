// Fuzz target of trace files (`multiray simulate TRACE`): balance::read_trace() on the
// input must return a trace or throw std::invalid_argument (trace.h). A trace it returns
// has frames, and each frame's items tile it (every pixel of every view once). It
// must survive a round trip: written and read again, it is written identically. A small
// one (at most 16 devices, 8 frames, 2^16 pixels a frame) is then replayed with the
// balancer it names, as `multiray simulate --validate` does, and every simulated frame
// time must be finite.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "balance/balancer.h"
#include "balance/trace.h"
#include "fuzz_support.h"
#include "partition/coverage.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace multiray;
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::istringstream in(text);
  balance::Trace trace;
  try {
    trace = balance::read_trace(in);
  } catch (const std::invalid_argument&) {
    return 0;
  }
  if (trace.frames.empty()) fuzz::fail("read_trace() accepted a trace without frames");
  for (const auto& f : trace.frames) {
    std::vector<balance::WorkItem> items;
    for (const auto& d : f.devices)
      for (const auto& r : d.items) items.push_back(r.item);
    const std::string wrong =
        balance::coverage_error(items, f.shape.width, f.shape.height, f.shape.views);
    if (!wrong.empty())
      fuzz::fail("read_trace() accepted a frame whose items do not tile it: " + wrong);
  }
  std::ostringstream once;
  balance::write_trace(once, trace);
  std::istringstream again_in(once.str());
  std::ostringstream twice;
  try {
    balance::write_trace(twice, balance::read_trace(again_in));
  } catch (const std::invalid_argument& e) {
    fuzz::fail(std::string("a written trace does not read back: ") + e.what());
  }
  if (once.str() != twice.str()) fuzz::fail("a trace changes when written and read again");

  const size_t devices = trace.devices.size();
  if (devices < 1 || devices > 16 || trace.frames.empty() || trace.frames.size() > 8) return 0;
  for (const auto& f : trace.frames)
    if (f.shape.pixels() > (int64_t(1) << 16)) return 0;
  std::unique_ptr<balance::Balancer> balancer;
  try {
    balancer = balance::make_balancer(trace.balancer, int(devices));
  } catch (const std::invalid_argument&) {
    return 0;
  }
  std::vector<balance::SimFrame> run;
  try {
    run = balance::replay_trace(trace, *balancer);
  } catch (const std::exception& e) {  // `simulate --validate` would call it an internal error
    fuzz::fail(std::string("replay_trace() of a trace read_trace() accepted throws: ") + e.what());
  }
  for (const auto& frame : run)
    if (!std::isfinite(frame.frame_ms)) fuzz::fail("a replayed frame time is not finite");
  return 0;
}
