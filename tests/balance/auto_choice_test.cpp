// `--balancer auto`'s rule table (balance/auto_choice.cpp), one test per row: each fails
// when its row changes, so a re-measured rule is changed here on purpose, with
// docs/balancers.md's table.
#include <gtest/gtest.h>

#include "balance/auto_choice.h"
#include "balance/balancer.h"

namespace multiray::balance {
namespace auto_choice_test {

// Devices named by type; an "opencl" one pays a fixed cost per item, as the OpenCL
// backend's registry entry says (the run layer reads it there: tests/device/).
AutoInputs devices(std::vector<std::string> types) {
  AutoInputs in;
  for (const std::string& t : types) in.devices.push_back(AutoDevice{t, 1, 1.0, t == "opencl"});
  return in;
}

bool says(const AutoChoice& c, const std::string& text) {
  return c.reason.find(text) != std::string::npos;
}

TEST(AutoChoice, OneDeviceRunsUniform) {
  for (const std::string type : {"cpu", "opencl", "remote", ""}) {
    AutoInputs in = devices({type});
    in.sampling = "foveated";  // ahead of the foveated row too
    const AutoChoice c = choose_balancer(in);
    EXPECT_EQ(c.spec, "uniform") << type;
    EXPECT_TRUE(says(c, "1 device") && says(c, "nothing to balance")) << c.reason;
  }
  EXPECT_EQ(choose_balancer(AutoInputs{}).spec, "uniform");  // none known
}

TEST(AutoChoice, AnOpenClDeviceRunsHybridWithItsPerItemCostModel) {
  const AutoChoice c = choose_balancer(devices({"cpu", "opencl", "cpu", "cpu", "cpu"}));
  EXPECT_EQ(c.spec, "hybrid");
  EXPECT_TRUE(says(c, "5 devices (cpu + opencl)")) << c.reason;
  EXPECT_TRUE(says(c, "fixed cost per item")) << c.reason;
  // Inside a worker rank, and ahead of the link's row.
  AutoInputs ranks = devices({"remote", "remote"});
  ranks.devices[1].item_cost = true;  // one of its own devices is an OpenCL device
  ranks.distributed = true;
  ranks.ranks = 3;
  EXPECT_TRUE(says(choose_balancer(ranks), "fixed cost per item"));
}

TEST(AutoChoice, OverALinkRunsHybrid) {
  AutoInputs in = devices({"remote", "remote", "remote"});
  in.distributed = true;
  in.ranks = 4;
  in.latency_ms = 5;
  in.mbit_per_s = 200;
  const AutoChoice c = choose_balancer(in);
  EXPECT_EQ(c.spec, "hybrid");
  EXPECT_TRUE(says(c, "4 ranks, link 5 ms, 200 Mbit/s")) << c.reason;
  EXPECT_TRUE(says(c, "overlaps results with rendering")) << c.reason;
  // A real transport (no emulated link) is still a link.
  in.latency_ms = in.mbit_per_s = 0;
  EXPECT_TRUE(says(choose_balancer(in), "overlaps results"));
}

TEST(AutoChoice, SeveralLocalDevicesRunHybrid) {
  const AutoChoice c = choose_balancer(devices({"cpu", "cpu", "cpu", "cpu", "cpu"}));
  EXPECT_EQ(c.spec, "hybrid");
  EXPECT_TRUE(says(c, "5 devices (cpu, one type)")) << c.reason;
  EXPECT_TRUE(says(c, "learns the devices' speeds")) << c.reason;
}

// Two to four devices of this machine: one contiguous piece each (measured best or tied
// on CPU + PoCL and the 3:1 pair, docs/benchmarks.md); over a link the bands stay.
TEST(AutoChoice, TwoToFourLocalDevicesRunHybridInOnePiece) {
  for (const std::vector<std::string>& types : {std::vector<std::string>{"cpu", "cpu"},
                                                {"cpu", "opencl"},
                                                {"cpu", "opencl", "opencl"},
                                                {"cpu", "cpu", "cpu", "cpu"}}) {
    const AutoChoice c = choose_balancer(devices(types));
    EXPECT_EQ(c.spec, "hybrid:bands=1") << c.reason;
    EXPECT_TRUE(says(c, "keeps its rays coherent")) << c.reason;
  }
  AutoInputs linked = devices({"remote", "remote"});
  linked.distributed = true;
  linked.ranks = 3;
  EXPECT_EQ(choose_balancer(linked).spec, "hybrid");
  AutoInputs emulated = devices({"cpu", "cpu"});
  emulated.latency_ms = 1;
  EXPECT_EQ(choose_balancer(emulated).spec, "hybrid");
}

// A shadow catcher concentrates a frame's cost around the virtual objects: hybrid's
// interleaved bands, not one piece per device (docs/benchmarks.md, "Augmented reality").
TEST(AutoChoice, AShadowCatcherKeepsHybridsInterleavedBands) {
  AutoInputs in = devices({"cpu", "cpu"});
  in.catcher = true;
  const AutoChoice c = choose_balancer(in);
  EXPECT_EQ(c.spec, "hybrid");
  EXPECT_TRUE(says(c, "2 devices (cpu, one type), shadow catcher")) << c.reason;
  EXPECT_TRUE(says(c, "gathers around the virtual objects")) << c.reason;
  in.devices.resize(1);
  EXPECT_EQ(choose_balancer(in).spec, "uniform");
  in.catcher = false;
  in.devices = devices({"cpu", "cpu"}).devices;
  EXPECT_EQ(choose_balancer(in).spec, "hybrid:bands=1");
}

TEST(AutoChoice, FoveatedSamplingRunsSemiStaticInRowBands) {
  AutoInputs in = devices({"cpu", "cpu"});
  in.sampling = "foveated";
  const AutoChoice c = choose_balancer(in);
  EXPECT_EQ(c.spec, "semi-static:split=rows:cdf=frame");
  EXPECT_TRUE(says(c, "rendered by both neighbours")) << c.reason;
  EXPECT_EQ(make_balancer(c.spec, 2)->spec(), "semi-static:alpha=0.4:split=rows:cdf=frame");
  in.devices[1] = devices({"opencl"}).devices[0];  // ahead of the fixed-cost row
  EXPECT_EQ(choose_balancer(in).spec, c.spec);
  in.devices.resize(1);
  EXPECT_EQ(choose_balancer(in).spec, "uniform");
}

// The rest of the workload selects no row of its own (auto_choice.cpp says why): a
// volume, a light field, adaptive or reprojected sampling and a frame-time target keep
// the devices' choice.
TEST(AutoChoice, TheRestOfTheWorkloadKeepsTheDevicesChoice) {
  for (const std::string sampling : {"uniform", "adaptive", "reproject"}) {
    AutoInputs in = devices({"cpu", "cpu"});
    in.sampling = sampling;
    in.views = 9;
    in.volume = sampling == "uniform";
    in.frame_target = true;
    EXPECT_EQ(choose_balancer(in).spec, "hybrid:bands=1") << sampling;
    in.devices.resize(1);
    EXPECT_EQ(choose_balancer(in).spec, "uniform") << sampling;
  }
}

TEST(AutoChoice, BuiltFromASpecItRunsTheChoiceForTheDeviceCount) {
  const auto one = make_balancer("auto", 1);
  const auto three = make_balancer("auto", 3);
  EXPECT_EQ(one->name(), "auto");
  EXPECT_EQ(one->spec(), "auto");
  EXPECT_EQ(dynamic_cast<const AutoBalancer&>(*one).choice().spec, "uniform");
  const AutoChoice& c = dynamic_cast<const AutoBalancer&>(*three).choice();
  EXPECT_EQ(c.spec, "hybrid:bands=1");
  EXPECT_TRUE(says(c, "only the device count was known")) << c.reason;
  EXPECT_EQ(three->cut_axis(), make_balancer("hybrid", 3)->cut_axis());
  EXPECT_THROW(make_balancer("auto:bands=4", 2), std::invalid_argument);
}

}  // namespace auto_choice_test
}  // namespace multiray::balance
