// make_balancer: every name builds, spec() round-trips, bad specs throw one-line errors.
#include <gtest/gtest.h>

#include <stdexcept>

#include "balance/balancer.h"

namespace multiray::balance {
namespace {

TEST(Spec, EveryNameBuildsAndSpecRoundTrips) {
  for (const std::string& name : balancer_names()) {
    const auto b = make_balancer(name, 3);
    EXPECT_EQ(b->name(), name);
    const auto again = make_balancer(b->spec(), 3);
    EXPECT_EQ(again->spec(), b->spec());
  }
}

TEST(Spec, ParametersAreRead) {
  EXPECT_EQ(make_balancer("queue:tile=32:batch=4", 2)->spec(), "queue:tile=32:batch=4");
  EXPECT_EQ(make_balancer("static:ratios=3/1", 2)->spec(), "static:ratios=3/1:layout=rows");
  EXPECT_EQ(make_balancer("dlb:interval=3:bits=6", 2)->spec(),
            "dlb:interval=3:band=0.1:slow=0.75:bits=6:layout=strips");
  EXPECT_EQ(make_balancer("uniform:layout=strips", 2)->spec(), "uniform:layout=strips");
  EXPECT_EQ(make_balancer("semi-static:alpha=0.25", 2)->spec(), "semi-static:alpha=0.25");
  EXPECT_NE(make_balancer("hybrid:bands=4:steal=off", 2)->spec().find("steal=0"),
            std::string::npos);
}

TEST(Spec, BadSpecsThrowOneLineMessages) {
  const std::vector<std::pair<std::string, int>> bad = {
      {"", 2},                       // no name
      {"fastest", 2},                // unknown name
      {"queue:tile=0", 2},           // out of range
      {"queue:tile=abc", 2},         // not a number
      {"queue:tile=12.5", 2},        // not an integer
      {"queue:tilesize=64", 2},      // unknown option
      {"queue:tile", 2},             // not key=value
      {"queue:tile=64:tile=32", 2},  // twice
      {"queue:", 2},                 // empty option
      {"static:ratios=3/1", 3},      // wrong count
      {"static:ratios=3/-1", 2},     // negative
      {"static:ratios=0/0", 2},      // nothing positive
      {"static:ratios=3/nan", 2},    // not finite
      {"semi-static:alpha=0", 2},    // alpha must be > 0
      {"semi-static:alpha=1.5", 2},  //
      {"dlb:bits=auto2", 2},         //
      {"dlb:slow=2", 2},             //
      {"dlb:layout=rows", 2},        //
      {"hybrid:steal=maybe", 2},     //
      {"uniform:layout=spiral", 2},  //
      {"uniform:=3", 2},             // empty key
      {"uniform", 0},                // no device
      {"uniform", 5000},             // too many
  };
  for (const auto& [spec, n] : bad) {
    try {
      make_balancer(spec, n);
      ADD_FAILURE() << "'" << spec << "' with " << n << " devices did not throw";
    } catch (const std::invalid_argument& e) {
      const std::string msg = e.what();
      EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
      EXPECT_NE(msg.find("balancer spec"), std::string::npos) << msg;
    }
  }
}

TEST(Spec, UnknownOptionMessageNamesTheKnownOnes) {
  try {
    make_balancer("dlb:intervall=5", 2);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("interval"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("intervall"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace multiray::balance
