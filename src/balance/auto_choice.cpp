#include "balance/auto_choice.h"

#include <algorithm>
#include <cstdio>

namespace multiray::balance {

namespace {

bool any_item_cost(const AutoInputs& in) {
  for (const AutoDevice& d : in.devices)
    if (d.item_cost) return true;
  return false;
}

bool over_a_link(const AutoInputs& in) {
  return in.distributed || in.latency_ms > 0 || in.mbit_per_s > 0;
}

// Two to four devices, all on this machine.
bool few_local(const AutoInputs& in) {
  return !over_a_link(in) && in.devices.size() >= 2 && in.devices.size() <= 4;
}

// One row of the table: the first row whose `applies` holds picks `spec`.
struct Rule {
  const char* when;  // the condition, as docs/balancers.md writes it
  bool (*applies)(const AutoInputs&);
  const char* spec;
  const char* why;
};

// THE RULE TABLE. Every row is backed by a figure in docs/benchmarks.md (named in the
// row's comment); a row without one does not belong here. The lead re-measures and edits
// this table (and docs/balancers.md's copy, and auto_choice_test.cpp's expectations).
//
// Inputs that select no row of their own, and why: the rest of the workload (mesh or
// volume, views, adaptive sampling, a frame-time target) - hybrid was best or tied:
// light fields -54% frame time against uniform and adaptive sampling at efficiency 0.97
// ("Light fields and adaptive sampling"), volumes at 0.864 and 0.993 against bruder's
// 0.802 and 0.934 ("Prediction-based balancing on CPU + PoCL"; queue within 1%); a
// frame-time target: no balancers compared yet. Many devices on a thin link: hybrid stays
// the most efficient at every count from 2 to 1024 on Wi-Fi ("Balancers at scale": 0.93
// at 16, 0.15 at 1024 where every balancer is bound by the master's link). Emulated CPU
// pairs: queue was 10-15% ahead of hybrid under heavy contention ("Hybrid's fixed cost per
// item ...", emulated 3:1 pair) but level on the real CPU + PoCL pair; not a rule until
// re-measured quietly.
const Rule kRules[] = {
    // Nothing to balance: the plainest plan, no learning, no stealing.
    {"one device", [](const AutoInputs& in) { return in.devices.size() <= 1; }, "uniform",
     "nothing to balance"},
    // "Foveated sampling": a device renders every sample whose disc reaches its rect, so
    // hybrid's ~40 pieces per device re-render border samples: efficiency 0.76-0.78 against
    // semi-static's 0.90-0.92 on a 2:1 pair (frames of 13.8/12.5 ms against 11.3/10.9 ms;
    // on four devices 14.8 against 13.9 ms, queue 12.1, but four devices on two cores were
    // a robustness test). That was semi-static's form before issue 13, spelt out here (row
    // bands, this frame's sample CDF).
    {"foveated sampling", [](const AutoInputs& in) { return in.sampling == "foveated"; },
     "semi-static:split=rows:cdf=frame",
     "foveated samples near a piece's border are rendered by both neighbours, so a few "
     "row bands split by samples beat hybrid's many pieces"},
    // "Augmented reality (issue 33)" and its re-run in session 9: with a shadow catcher a
    // frame's cost gathers where the virtual objects are (a sky pixel costs one ray, the
    // ground a light sample and a bounce, the objects whole paths), and it moves as the
    // camera orbits. hybrid's 8 interleaved bands spread it over the devices; one piece
    // each (the next row) was 2.2% slower on an even pair (1.022x [1.019, 1.025] per
    // frame, efficiency 0.948 against 0.972) and 0.2% on a 3:1 pair (1.002x [1.001,
    // 1.005]); on the whole scene without a catcher the two were tied. (The catcher is a
    // CPU path-kernel feature, so only local CPU devices reach this row.)
    {"a shadow catcher (--ground)", [](const AutoInputs& in) { return in.catcher; }, "hybrid",
     "with a shadow catcher the frame's cost gathers around the virtual objects and moves "
     "with the camera; hybrid's interleaved bands spread it over the devices"},
    // "Ours on real devices (issue 30, second part)": on two to four devices of this machine
    // (no link) one contiguous piece per device keeps each device's rays and texture
    // reads coherent. hybrid:bands=1 was the best or tied with the best on CPU + PoCL
    // (Sponza 0.968, the default scene 0.970, DamagedHelmet 0.959 tied with semi-static)
    // and on the 3:1 CPU pair, with and without a slowdown; the default 8 interleaved
    // bands were 1-4% slower there. Stealing still takes the tail. More devices, or a
    // link, keep the bands: their speeds are measured on pieces spread over the frame.
    {"2 to 4 devices on this machine (no link)", few_local, "hybrid:bands=1",
     "one contiguous piece per device keeps its rays coherent; stealing takes the tail"},
    // "Hybrid's fixed cost per item on real devices": measured on an OpenCL device, the
    // GPU-style backend whose every launch costs the same. On CPU + PoCL the per-item cost model
    // (overhead=0.1, the default) cut mean frame time by 3.0-5.8% against overhead=0, and
    // hybrid beat semi-static, equalizer, cycles and both OSPRay balancers in every run;
    // with batched launches it is the most efficient there (0.964, "Fewer, cheaper items").
    {"a device with a fixed cost per item (a kernel launch)", any_item_cost, "hybrid",
     "a device pays a fixed cost per item (a kernel launch), which hybrid's per-item cost "
     "model (overhead=0.1) learns and keeps its chunks above"},
    // "Balancers at scale" (simulated): the most efficient balancer at every device count
    // on both links (Wi-Fi, 16 devices: 0.93; LAN, 64: 0.88); it overlaps results with
    // rendering, so compressed results change nothing for it ("Fewer, cheaper items").
    {"a link (--distributed or an emulated link)", over_a_link, "hybrid",
     "over a link hybrid overlaps results with rendering and was the most efficient "
     "balancer at 2 to 1024 simulated devices on LAN and Wi-Fi"},
    // "Balancers on two CPU devices, 3:1 emulated": the lowest imbalance (0.6-2.0%) and
    // the largest speed-up over uniform (queue level) in each; "Hybrid's fixed cost per item":
    // level with queue and ahead of the one-range balancers on the CPU + PoCL pair.
    {"several devices", [](const AutoInputs&) { return true; }, "hybrid",
     "hybrid learns the devices' speeds and steals the frame's tail"},
};

// "2 devices (cpu + opencl)", "3 devices (remote, one type), 4 ranks, link 5 ms, 200 Mbit/s".
std::string describe(const AutoInputs& in) {
  std::vector<std::string> types;
  for (const AutoDevice& d : in.devices) {
    const std::string t = d.type.empty() ? "unknown type" : d.type;
    if (std::find(types.begin(), types.end(), t) == types.end()) types.push_back(t);
  }
  const size_t n = in.devices.size();
  std::string text = std::to_string(n) + (n == 1 ? " device" : " devices");
  if (!types.empty() && !(types.size() == 1 && types[0] == "unknown type")) {
    text += " (";
    for (size_t i = 0; i < types.size(); ++i) text += (i ? " + " : "") + types[i];
    text += types.size() == 1 && n > 1 ? ", one type)" : ")";
  }
  if (in.distributed) text += ", " + std::to_string(in.ranks) + " ranks";
  if (in.catcher) text += ", shadow catcher";
  if (in.latency_ms > 0 || in.mbit_per_s > 0) {
    char link[96];
    std::snprintf(link, sizeof link, ", link %g ms, %g Mbit/s", in.latency_ms, in.mbit_per_s);
    text += link;
  }
  return text;
}

}  // namespace

AutoChoice choose_balancer(const AutoInputs& in) {
  for (const Rule& r : kRules)
    if (r.applies(in)) return {r.spec, describe(in) + "; " + r.why};
  return {"hybrid", describe(in)};  // unreachable: the last rule always applies
}

AutoBalancer::AutoBalancer(int device_count) {
  AutoInputs in;
  in.devices.resize(size_t(std::max(device_count, 0)));
  choice_ = choose_balancer(in);
  choice_.reason += " (only the device count was known)";
  chosen_ = make_balancer(choice_.spec, device_count);
}

}  // namespace multiray::balance
