// Fuzz target of transfer-function files (`--tf FILE`): parse_transfer_function() on the
// input must return a function that check_transfer_function() accepts, or throw an
// InputError. A function it returns is resolved on a small volume, baked and evaluated:
// every table entry and value must be finite, opacities in [0, 1], and the maximum over an
// interval no smaller than the function at its ends.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "core/error.h"
#include "fuzz_support.h"
#include "volume/transfer_function.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace multiray;
  const std::string text(reinterpret_cast<const char*>(data), size);
  TransferFunction tf;
  try {
    tf = parse_transfer_function(text, "fuzz.json");
  } catch (const InputError&) {
    return 0;
  }
  try {
    check_transfer_function(tf, "fuzz.json");
  } catch (const InputError& e) {
    fuzz::fail(std::string("a parsed transfer function fails its check: ") + e.what());
  }
  Volume v;
  v.nx = v.ny = v.nz = 2;
  v.values = {-1024, 0, 1, 2, 100, 255, 1000, 3000};
  v.min_value = -1024, v.max_value = 3000;
  const TransferFunction r = resolve(tf, v);
  const TransferTable table = bake(r, v.min_value, v.max_value, 64);
  for (const auto& e : table.rgba)
    for (float c : e)
      if (!std::isfinite(c) || c < 0 || c > 1) fuzz::fail("a baked table entry is out of range");
  for (float x : v.values) {
    const auto e = evaluate(r, x);
    const float m = max_opacity(r, x, x + 10);
    if (!std::isfinite(m) || m + 1e-6f < e[3]) fuzz::fail("max_opacity is below the function");
  }
  return 0;
}
