#include "device/backend_options.h"

#include <algorithm>
#include <cctype>
#include <limits>
#include <stdexcept>
#include <string>

#include "device/scene_memory.h"
#include "util/parse.h"

namespace multiray::backend_options {

BackendParam speed_param() {
  return {"speed", "[0.01, 1]", "1",
          "emulated speed: the device idles after each item (always labelled emulated)"};
}
BackendParam cores_param() { return {"cores", "0, 0+2, 0-3", "", "cores to pin to"}; }
BackendParam compact_param() {
  return {"compact", "0 or 1", "0", "trace the compact scene (quantized mesh and tree)"};
}
BackendParam mem_param() {
  return {"mem", "1M..1024T", "",
          "emulated memory limit (512M, 2G): a scene that does not fit the representation is "
          "refused"};
}
BackendParam fail_after_param() {
  // No default: without the key the device never fails; fail_after=0 fails at the
  // first item.
  return {"fail_after", "0..2^31-1", "",
          "testing aid: the device fails when it takes an item after this many (0: at once)"};
}

LoopOptions read_loop_options(Spec& spec) {
  LoopOptions o;
  o.speed = spec.get_double("speed", o.speed, kMinEmulatedSpeed, 1.0);  // emulated
  o.fail_after = spec.get_int("fail_after", o.fail_after, 0, std::numeric_limits<int>::max());
  return o;
}

void read_memory_options(Spec& spec, bool& compact, uint64_t& limit) {
  compact = spec.get_bool("compact", compact);
  if (!spec.has("mem")) return;
  const std::string text = spec.get_string("mem", "", {});
  try {
    limit = parse_memory_size(text);
  } catch (const std::invalid_argument& e) {
    spec.fail(e.what());
  }
}

namespace {

// A core id: decimal digits only, below 100000 (so "-1", "1.5" and "0x2" are no ids).
int core_id(const std::string& s) {
  if (s.empty() || s.size() > 5 ||
      !std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isdigit(c); }))
    return -1;
  return std::stoi(s);
}

}  // namespace

std::vector<int> read_cores(Spec& spec) {
  const std::string list = spec.get_string("cores", "", {});
  if (!spec.has("cores")) return {};
  std::vector<int> cores;
  size_t start = 0;
  for (;;) {
    const size_t plus = list.find('+', start);
    const std::string part = list.substr(start, plus - start);
    const size_t dash = part.find('-');
    const int a = core_id(part.substr(0, dash));
    const int b = dash == std::string::npos ? a : core_id(part.substr(dash + 1));
    if (a < 0 || b < a || b - a > 4096)
      spec.fail("cores=" + list + " is not a core list like 0, 0+2 or 0-3");
    for (int c = a; c <= b; ++c) cores.push_back(c);
    if (plus == std::string::npos) return cores;
    start = plus + 1;
  }
}

}  // namespace multiray::backend_options
