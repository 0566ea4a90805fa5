// make_balancer: every name builds, spec() round-trips, bad specs throw one-line errors.
// Spec itself: typed getters check ranges on the converted value, the positional value
// is opt-in, unknown keys are named with the known ones, lists split at commas.
#include <gtest/gtest.h>

#include <stdexcept>

#include "balance/balancer.h"
#include "util/spec.h"

namespace multiray::balance {
namespace spec_test {

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
  EXPECT_EQ(make_balancer("queue:pipeline=deep", 2)->spec(),
            "queue:tile=64:batch=1:pipeline=deep");
  EXPECT_EQ(make_balancer("static:ratios=3/1", 2)->spec(), "static:ratios=3/1:layout=rows");
  EXPECT_EQ(make_balancer("dlb:interval=3:bits=6", 2)->spec(),
            "dlb:interval=3:band=0.1:slow=0.75:bits=6:strip=32:items=16384:layout=strips");
  EXPECT_EQ(make_balancer("uniform:layout=strips", 2)->spec(),
            "uniform:layout=strips:bits=auto:strip=32:items=16384");
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

// The message of the std::invalid_argument `f` throws ("" when it throws none).
template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

TEST(Spec, IntGetterChecksTheRangeOfTheInt) {
  for (const std::string v : {"1e10", "-1e10", "2.5", "nan", "inf", "", " 3", "3x", "0x", "5"}) {
    Spec spec("n:k=" + v);
    const std::string msg = error_of([&] { spec.get_int("k", 1, 1, 4); });
    EXPECT_TRUE(contains(msg, "balancer spec 'n:k=" + v + "': k=")) << v << ": " << msg;
  }
  Spec big("n:k=2147483648");  // one past INT_MAX, even though hi is INT_MAX
  EXPECT_TRUE(contains(error_of([&] { big.get_int("k", 0, 0, 2147483647); }), "outside"));
  Spec ok("n:a=7:b=2.0:c=1e3:d=-3");
  EXPECT_EQ(ok.get_int("a", 0, 0, 10), 7);
  EXPECT_EQ(ok.get_int("b", 0, 0, 10), 2);
  EXPECT_EQ(ok.get_int("c", 0, 0, 1000), 1000);
  EXPECT_EQ(ok.get_int("d", 0, -3, 0), -3);
  EXPECT_EQ(ok.get_int("absent", 42, 0, 1), 42);  // the fallback is not range-checked
  EXPECT_NO_THROW(ok.finish());
}

TEST(Spec, PositiveGetterExcludesZero) {
  Spec spec("n:a=0.5:b=0:c=1.5:d=1e-300");
  EXPECT_EQ(spec.get_positive("a", 1, 1), 0.5);
  EXPECT_TRUE(contains(error_of([&] { spec.get_positive("b", 1, 1); }), "b=0 is outside (0, 1]"));
  EXPECT_TRUE(contains(error_of([&] { spec.get_positive("c", 1, 1); }), "outside"));
  EXPECT_GT(spec.get_positive("d", 1, 1), 0);
}

TEST(Spec, PositionalValueIsOptIn) {
  EXPECT_TRUE(contains(error_of([] { Spec("queue:32"); }), "option '32' is not key=value"));
  SpecSyntax syntax;
  syntax.label = "--devices";
  syntax.positional_key = "index";
  Spec spec("opencl:3:wg=32", syntax);
  EXPECT_EQ(spec.name(), "opencl");
  EXPECT_EQ(spec.options().at("index"), "3");
  EXPECT_EQ(spec.get_int("index", 0, 0, 9), 3);
  EXPECT_EQ(spec.get_int("wg", 0, 1, 64), 32);
  EXPECT_FALSE(Spec("opencl", syntax).has("index"));
  EXPECT_EQ(Spec("opencl:index=2", syntax).options().at("index"), "2");
  // Only right after the name, at most once, and never empty.
  EXPECT_TRUE(contains(error_of([&] { Spec("opencl:wg=32:3", syntax); }), "'3' is not key=value"));
  EXPECT_TRUE(contains(error_of([&] { Spec("opencl:1:index=2", syntax); }), "given twice"));
  EXPECT_TRUE(contains(error_of([&] { Spec("opencl::wg=3", syntax); }), "not key=value"));
  EXPECT_EQ(error_of([&] { Spec("opencl:0:wg", syntax); }).rfind("--devices 'opencl:0:wg': ", 0),
            0u);
}

TEST(Spec, AcceptOnlyListsTheKnownKeys) {
  Spec spec("cpu:threads=2:colour=red");
  const std::string msg = error_of([&] { spec.accept_only({"tile", "threads"}); });
  EXPECT_TRUE(contains(msg, "unknown option 'colour' for cpu (known: threads, tile)")) << msg;
  EXPECT_NO_THROW(Spec("cpu:threads=2").accept_only({"tile", "threads"}));
  // finish() lists the keys the getters asked for.
  spec.get_int("threads", 1, 1, 8);
  EXPECT_TRUE(contains(error_of([&] { spec.finish(); }), "'colour' for cpu (known: threads)"));
}

TEST(Spec, ListSplitsAtEveryComma) {
  EXPECT_EQ(split_spec_list(""), std::vector<std::string>{});
  EXPECT_EQ(split_spec_list("dlb"), std::vector<std::string>{"dlb"});
  EXPECT_EQ(split_spec_list("queue:tile=8,dlb"),
            (std::vector<std::string>{"queue:tile=8", "dlb"}));
  EXPECT_EQ(split_spec_list("a,,b"), (std::vector<std::string>{"a", "", "b"}));
  EXPECT_EQ(split_spec_list("a,"), (std::vector<std::string>{"a", ""}));
}

}  // namespace spec_test
}  // namespace multiray::balance
