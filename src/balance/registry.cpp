#include "balance/registry.h"

#include <algorithm>
#include <stdexcept>

#include "balance/auto_choice.h"
#include "balance/bruder.h"
#include "balance/dlb.h"
#include "balance/hybrid.h"
#include "balance/layout.h"
#include "balance/peers_cycles.h"
#include "balance/peers_equalizer.h"
#include "balance/peers_ospray.h"
#include "balance/queue.h"
#include "balance/semi_static.h"
#include "balance/static_ratios.h"
#include "balance/subset.h"
#include "balance/uniform.h"

namespace multiray::balance {

namespace {

Layout get_layout(Spec& spec) {
  return layout_from_string(spec.get_string("layout", "rows", layout_names()));
}

const ParamInfo kLayout{"layout", "rows", "rows|columns|strips|views",
                        "how each device's share is laid out"};
const ParamInfo kTile{"tile", "64", "1..4096", "tile side, pixels"};
// The strips of layout=strips (layout.h StripRule), the same for uniform, static and dlb.
const ParamInfo kBits{"bits", "auto", "auto|0..24", "log2 of the strips per view"};
const ParamInfo kStrip{"strip", "32", "1..65536", "least pixels per strip with bits=auto"};
const ParamInfo kItems{"items", "16384", "1..16777216", "most strips per frame with bits=auto"};

StripRule get_strips(Spec& spec) {
  StripRule r;
  if (spec.get_string("bits", "auto", {}) != "auto") r.bits = spec.get_int("bits", -1, 0, 24);
  r.min_strip = spec.get_int("strip", r.min_strip, 1, 65536);
  r.max_items = spec.get_int("items", r.max_items, 1, 1 << 24);
  return r;
}

std::unique_ptr<Balancer> make_semi_static(Spec& spec, int n) {
  SemiStaticOptions o;
  o.alpha = spec.get_double("alpha", 0.4, 1e-6, 1.0);
  o.split = spec.get_string("split", "columns", {"columns", "rows"}) == "rows" ? LineAxis::rows
                                                                               : LineAxis::columns;
  o.cdf_from_frame = spec.get_string("cdf", "reported", {"reported", "frame"}) == "frame";
  o.whole_lines = spec.get_string("cut", "pixel", {"pixel", "line"}) == "line";
  return std::make_unique<SemiStaticBalancer>(n, o);
}

std::unique_ptr<Balancer> make_dlb(Spec& spec, int n) {
  const int interval = spec.get_int("interval", 5, 1, 1000);
  const double band = spec.get_double("band", 0.1, 0.0, 10.0);
  const double slow = spec.get_double("slow", 0.75, 0.0, 1.0);
  const StripRule strips = get_strips(spec);
  const std::string layout = spec.get_string("layout", "strips", {"strips", "views"});
  return std::make_unique<DlbBalancer>(n, interval, band, slow, strips,
                                       layout_from_string(layout));
}

std::unique_ptr<Balancer> make_hybrid(Spec& spec, int n) {
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
  o.detect_noise = spec.get_string("detect", "noise", {"noise", "fixed"}) == "noise";
  o.z = spec.get_double("z", o.z, 1.0, 100.0);
  o.frame_cost = spec.get_bool("frame", o.frame_cost);
  o.leave = spec.get_bool("leave", o.leave);
  o.probe = spec.get_int("probe", o.probe, 0, 1000);
  return std::make_unique<HybridBalancer>(n, o);
}

std::unique_ptr<Balancer> make_bruder(Spec& spec, int n) {
  BruderBalancer::Options o;
  o.zeta = spec.get_double("zeta", o.zeta, 0.0, 1.0);
  o.tile = spec.get_int("tile", o.tile, 1, 4096);
  o.steal = spec.get_bool("steal", o.steal);
  o.items = spec.get_string("items", o.items, {"rect", "rows", "tiles"});
  o.fixed_cost = spec.get_ratios("sigma", size_t(n));
  return std::make_unique<BruderBalancer>(n, o);
}

std::vector<BalancerEntry> builtin_balancers() {
  return {
      {"uniform",
       "every device gets 1/N of every view (the baseline)",
       "Leria et al. 2025, Algorithms 1-2",
       {kLayout, kBits, kStrip, kItems},
       [](Spec& s, int n) {
         const Layout layout = get_layout(s);
         return std::make_unique<UniformBalancer>(n, layout, get_strips(s));
       }},
      {"static",
       "fixed ratios, given or measured on the first frame",
       "ours (a baseline; the papers' static forms are ospray-static and bruder:sigma=)",
       {{"ratios", "measured", "A/B/...", "one non-negative number per device"},
        kLayout,
        kBits,
        kStrip,
        kItems},
       [](Spec& s, int n) {
         std::vector<double> ratios = s.get_ratios("ratios", size_t(n));
         const Layout layout = get_layout(s);
         return std::make_unique<StaticBalancer>(n, std::move(ratios), layout, get_strips(s));
       }},
      {"queue",
       "a shared queue of tiles that idle devices pull",
       "Seo, Park & Ihm 2022, strategy I (dynamic interaction)",
       {kTile,
        {"batch", "1", "1..1024", "tiles taken per pull"},
        {"pipeline", "paper", "paper|deep",
         "to a worker rank: one tile, the next on its ready report; deep: --depth (ours)"}},
       [](Spec& s, int n) {
         const int tile = s.get_int("tile", 64, 1, 4096);
         const int batch = s.get_int("batch", 1, 1, 1024);
         const bool deep = s.get_string("pipeline", "paper", {"paper", "deep"}) == "deep";
         return std::make_unique<QueueBalancer>(n, tile, batch, deep);
       }},
      {"semi-static",
       "one contiguous range per device, shares from last frame's speeds",
       "Harada, Semi-static Load Balancing ... (GPU Pro 7, 2016)",
       {{"alpha", "0.4", "(0, 1]", "weight of the new ideal share"},
        {"split", "columns", "columns|rows", "cut the image into column or row bands"},
        {"cdf", "reported", "reported|frame",
         "samples from last frame's reports or this frame's map"},
        {"cut", "pixel", "pixel|line", "cut at pixel precision or at whole lines"}},
       make_semi_static},
      {"dlb",
       "shuffled strips per view, ratios revisited every few frames",
       "Leria et al., Dynamic load balancing for real-time multiview path tracing (2025)",
       {{"interval", "5", "1..1000", "frames between checks"},
        {"band", "0.1", "0..10", "tolerated relative difference of device times"},
        {"slow", "0.75", "0..1", "weight of a slow device's window mean"},
        kBits,
        kStrip,
        kItems,
        {"layout", "strips", "strips|views", "strips of every view, or whole views (ours)"}},
       make_dlb},
      {"hybrid",
       "equal-cost bands split by learnt speeds, chunks stolen from the back",
       "ours",
       {{"bands", "8", "1..256", "interleaved bands of equal cost: pieces per device"},
        {"taper", "0.7", "0..0.95", "a chunk is at most (1 - taper) of what its device has left"},
        {"tail", "0.02", "0.0001..1", "smallest chunk, in units of the slowest device's share"},
        {"alpha", "0.5", "(0, 1]", "weight of a new speed measurement"},
        {"jump", "0.2", "0..1e9",
         "relative speed change taken at once (detect=noise: until 4 measurements)"},
        {"gamma", "0.5", "0..1", "weight of a new row-cost observation"},
        {"min_chunk", "256", "1..1073741824", "smallest chunk in pixels; shorter ones merge"},
        {"steal", "1", "0|1", "0: a pure bulk split (for comparison)"},
        {"overhead", "0.1", "0..0.9", "most of a chunk's time a fixed cost per item may take"},
        {"detect", "noise", "noise|fixed",
         "a speed change is judged against the device's own noise, or by jump alone (before)"},
        {"z", "3", "1..100", "detect=noise: a change lies beyond z sigmas of the noise"},
        {"frame", "1", "0|1", "learn and plan with a fixed cost per frame (0: none, before)"},
        {"leave", "1", "0|1",
         "leave out a device whose fixed cost per frame outweighs its share (0: never)"},
        {"probe", "8", "0..1000",
         "frames before a left-out device is probed again (doubling to 8x); 0: never"}},
       make_hybrid},
      {"bruder",
       "predicted costs, a k-d tree of tiles cut at the devices' shares",
       "Bruder et al., Prediction-based load balancing ... (Visual Informatics 2017)",
       {{"zeta", "0.5", "0..1", "weight of the predicted shares against uniform (Eq. 3's zeta)"},
        {"tile", "8", "1..4096", "tile side, pixels (the paper: 8)"},
        {"steal", "0", "0|1", "1: idle devices steal (ours; the paper does not)"},
        {"items", "rows", "rect|rows|tiles", "how a device's region is handed out"},
        {"sigma", "measured", "A/B/...",
         "fixed cost per sample, one per device > 0: the paper's 7.5 static baseline "
         "(absent: predicted, else measured)"}},
       make_bruder},
      {"subset",
       "some devices only, split by hybrid:bands=1:leave=0; the others left out",
       "ours (a baseline: the regret table of bench --regret)",
       {{"devices", "all", "0+2+...",
         "the devices that render, by index (--devices order), joined by +"}},
       [](Spec& s, int n) {
         const std::string list = s.get_string("devices", "all", {});
         std::vector<int> members;
         if (list == "all")
           for (int d = 0; d < n; ++d) members.push_back(d);
         else
           members = SubsetBalancer::parse_members(list, n);
         return std::make_unique<SubsetBalancer>(n, std::move(members));
       }},
      // Not a method: picks one of the above (auto_choice.h). Built here with only the
      // device count known; the run layer resolves it from the devices and the link.
      {"auto",
       "chosen from the devices, the link and the workload (the default of render and view)",
       "ours",
       {},
       [](Spec&, int n) { return std::make_unique<AutoBalancer>(n); }},
      // The peers' balancers (peers_*.h), for comparison.
      {"cycles",
       "Blender Cycles' multi-device balancing",
       "Blender Cycles (work balancer)",
       {{"interval_ms", "1000", "0..1e9", "time between rebalances"}},
       [](Spec& s, int n) {
         return std::make_unique<CyclesBalancer>(n, s.get_double("interval_ms", 1000, 0, 1e9));
       }},
      {"equalizer",
       "Equalizer's load equalizer, 2D",
       "Equalizer (LoadEqualizer)",
       {{"damping", "0.5", "0..1", "weight of the previous split"}},
       [](Spec& s, int n) {
         return std::make_unique<EqualizerBalancer>(n, s.get_double("damping", 0.5, 0, 1));
       }},
      {"ospray-static",
       "OSPRay MPI: tiles owned round-robin",
       "OSPRay MPI module",
       {kTile},
       [](Spec& s, int n) {
         return std::make_unique<OsprayStaticBalancer>(n, s.get_int("tile", 64, 1, 4096));
       }},
      {"ospray-dynamic",
       "OSPRay MPI: tiles handed out on request",
       "OSPRay MPI module",
       {kTile, {"prefetch", "4", "1..1024", "tiles a device holds ahead"}},
       [](Spec& s, int n) {
         const int tile = s.get_int("tile", 64, 1, 4096);
         const int prefetch = s.get_int("prefetch", 4, 1, 1024);
         return std::make_unique<OsprayDynamicBalancer>(n, tile, prefetch);
       }},
  };
}

std::vector<BalancerEntry>& registry() {
  static std::vector<BalancerEntry> entries = builtin_balancers();
  return entries;
}

}  // namespace

const std::vector<BalancerEntry>& balancer_registry() { return registry(); }

bool valid_balancer_name(const std::string& name) {
  const auto allowed = [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
           c == '-' || c == '_';
  };
  return !name.empty() && std::all_of(name.begin(), name.end(), allowed);
}

void register_balancer(BalancerEntry entry) {
  if (entry.name.empty() || !entry.make)
    throw std::invalid_argument("register_balancer: an entry needs a name and a factory");
  // A name a spec cannot carry could never be chosen, and would corrupt what carries it
  // (a newline a trace's "balancer" line, a comma a list of specs).
  if (!valid_balancer_name(entry.name))
    throw std::invalid_argument("register_balancer: '" + entry.name +
                                "' is not a balancer name (letters, digits, '-' and '_' only)");
  if (find_balancer(entry.name))
    throw std::invalid_argument("register_balancer: '" + entry.name + "' is already registered");
  registry().push_back(std::move(entry));
}

const BalancerEntry* find_balancer(const std::string& name) {
  for (const BalancerEntry& e : registry())
    if (e.name == name) return &e;
  return nullptr;
}

std::string usage(const BalancerEntry& e) {
  std::string text = e.name;
  for (const ParamInfo& p : e.params) text += "[:" + p.key + "=" + p.fallback + "]";
  return text;
}

std::string balancer_help() {
  std::string text;
  for (const BalancerEntry& e : registry()) text += "  " + usage(e) + "\n      " + e.help + "\n";
  return text;
}

}  // namespace multiray::balance
