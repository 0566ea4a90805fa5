#include "balance/balancer.h"

#include "balance/bruder.h"
#include "balance/dlb.h"
#include "balance/hybrid.h"
#include "balance/layout.h"
#include "balance/peers_cycles.h"
#include "balance/peers_equalizer.h"
#include "balance/peers_ospray.h"
#include "balance/queue.h"
#include "balance/semi_static.h"
#include "balance/spec.h"
#include "balance/static_ratios.h"
#include "balance/uniform.h"

namespace multiray::balance {

namespace {
Layout get_layout(Spec& spec) {
  return layout_from_string(spec.get_string("layout", "rows", layout_names()));
}

std::unique_ptr<Balancer> build(Spec& spec, int n) {
  const std::string& name = spec.name();
  if (name == "uniform") return std::make_unique<UniformBalancer>(n, get_layout(spec));
  if (name == "static") {
    std::vector<double> ratios = spec.get_ratios("ratios", size_t(n));
    return std::make_unique<StaticBalancer>(n, std::move(ratios), get_layout(spec));
  }
  if (name == "queue") {
    const int tile = spec.get_int("tile", 64, 1, 4096);
    const int batch = spec.get_int("batch", 1, 1, 1024);
    return std::make_unique<QueueBalancer>(n, tile, batch);
  }
  if (name == "semi-static") {
    SemiStaticOptions o;
    o.alpha = spec.get_double("alpha", 0.4, 1e-6, 1.0);
    o.split = spec.get_string("split", "columns", {"columns", "rows"}) == "rows"
                  ? LineAxis::rows
                  : LineAxis::columns;
    o.cdf_from_frame = spec.get_string("cdf", "reported", {"reported", "frame"}) == "frame";
    return std::make_unique<SemiStaticBalancer>(n, o);
  }
  if (name == "dlb") {
    const int interval = spec.get_int("interval", 5, 1, 1000);
    const double band = spec.get_double("band", 0.1, 0.0, 10.0);
    const double slow = spec.get_double("slow", 0.75, 0.0, 1.0);
    int bits = -1;  // "auto": from the least pixels per strip (dlb.h)
    if (spec.get_string("bits", "auto", {}) != "auto") bits = spec.get_int("bits", -1, 0, 24);
    const int strip = spec.get_int("strip", 32, 1, 65536);
    const int items = spec.get_int("items", 16384, 1, 1 << 24);
    const std::string layout = spec.get_string("layout", "strips", {"strips", "views"});
    return std::make_unique<DlbBalancer>(n, interval, band, slow, bits, layout_from_string(layout),
                                         strip, items);
  }
  if (name == "hybrid") {
    HybridBalancer::Options o;
    o.bands = spec.get_int("bands", o.bands, 1, 256);
    o.taper = spec.get_double("taper", o.taper, 0.0, 0.95);
    o.tail = spec.get_double("tail", o.tail, 1e-4, 1.0);
    o.alpha = spec.get_double("alpha", o.alpha, 1e-6, 1.0);
    o.jump = spec.get_double("jump", o.jump, 0.0, 1e9);
    o.gamma = spec.get_double("gamma", o.gamma, 0.0, 1.0);
    o.min_chunk = spec.get_int("min_chunk", o.min_chunk, 1, 1 << 30);
    o.steal = spec.get_bool("steal", o.steal);
    o.overhead = spec.get_double("overhead", o.overhead, 0.0, 0.9);
    return std::make_unique<HybridBalancer>(n, o);
  }
  if (name == "bruder") {
    BruderBalancer::Options o;
    o.zeta = spec.get_double("zeta", o.zeta, 0.0, 1.0);
    o.tile = spec.get_int("tile", o.tile, 1, 4096);
    o.steal = spec.get_bool("steal", o.steal);
    o.items = spec.get_string("items", o.items, {"rect", "rows", "tiles"});
    return std::make_unique<BruderBalancer>(n, o);
  }
  // The peers' balancers (peers_*.h), for comparison.
  if (name == "cycles")
    return std::make_unique<CyclesBalancer>(n, spec.get_double("interval_ms", 1000, 0, 1e9));
  if (name == "equalizer")
    return std::make_unique<EqualizerBalancer>(n, spec.get_double("damping", 0.5, 0, 1));
  if (name == "ospray-static")
    return std::make_unique<OsprayStaticBalancer>(n, spec.get_int("tile", 64, 1, 4096));
  if (name == "ospray-dynamic") {
    const int tile = spec.get_int("tile", 64, 1, 4096);
    const int prefetch = spec.get_int("prefetch", 4, 1, 1024);
    return std::make_unique<OsprayDynamicBalancer>(n, tile, prefetch);
  }
  std::string known;
  for (const std::string& b : balancer_names()) known += (known.empty() ? "" : ", ") + b;
  spec.fail("unknown balancer '" + name + "' (known: " + known + ")");
}
}  // namespace

std::vector<std::string> balancer_names() {
  return {"uniform", "static", "queue",     "semi-static",   "dlb",           "hybrid",
          "bruder",  "cycles", "equalizer", "ospray-static", "ospray-dynamic"};
}

std::unique_ptr<Balancer> make_balancer(const std::string& text, int device_count) {
  Spec spec(text);
  if (device_count < 1 || device_count > 4096)
    spec.fail("device count " + std::to_string(device_count) + " is outside 1..4096");
  std::unique_ptr<Balancer> balancer = build(spec, device_count);
  spec.finish();
  return balancer;
}

}  // namespace multiray::balance
