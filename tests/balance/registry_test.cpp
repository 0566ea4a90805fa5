// The balancer registry holds what every list of balancers is made from: each entry builds
// with its defaults, its factory asks for exactly the options it declares, each declared
// default is accepted, the help and docs/balancers.md name every balancer and option, and
// a balancer added from outside (a toy, here) is built, listed and refused twice.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <set>
#include <sstream>

#include "balance/registry.h"
#include "balance/uniform.h"

namespace multiray::balance {
namespace registry_test {

std::set<std::string> declared(const BalancerEntry& e) {
  std::set<std::string> keys;
  for (const ParamInfo& p : e.params) keys.insert(p.key);
  return keys;
}

TEST(Registry, EveryFactoryAsksForExactlyTheOptionsItDeclares) {
  ASSERT_GE(balancer_registry().size(), 11u);
  for (const BalancerEntry& e : balancer_registry())
    for (int devices : {1, 2, 5}) {
      Spec spec(e.name);
      ASSERT_NE(e.make(spec, devices), nullptr) << e.name;
      const std::set<std::string> asked(spec.asked().begin(), spec.asked().end());
      EXPECT_EQ(asked, declared(e)) << e.name;
    }
}

TEST(Registry, EveryDeclaredDefaultIsAccepted) {
  for (const BalancerEntry& e : balancer_registry())
    for (const ParamInfo& p : e.params) {
      if (p.fallback == "measured") continue;  // static's ratios: absent means measured
      const std::string spec = e.name + ":" + p.key + "=" + p.fallback;
      EXPECT_NO_THROW(make_balancer(spec, 2)) << spec;
      EXPECT_FALSE(p.help.empty() || p.values.empty()) << spec;
    }
}

TEST(Registry, NamesHelpAndDocsComeFromIt) {
  std::vector<std::string> names;
  for (const BalancerEntry& e : balancer_registry()) names.push_back(e.name);
  EXPECT_EQ(balancer_names(), names);
  const std::string help = balancer_help();
  std::ifstream in(std::string(MULTIRAY_SOURCE_DIR) + "/docs/balancers.md");
  ASSERT_TRUE(in) << "docs/balancers.md";
  std::stringstream docs;
  docs << in.rdbuf();
  for (const BalancerEntry& e : balancer_registry()) {
    EXPECT_NE(help.find(usage(e)), std::string::npos) << e.name;
    EXPECT_NE(help.find(e.help), std::string::npos) << e.name;
    EXPECT_FALSE(e.help.empty() || e.credit.empty()) << e.name;
    EXPECT_NE(docs.str().find("`" + e.name), std::string::npos) << e.name << " in the docs";
    for (const ParamInfo& p : e.params)
      EXPECT_NE(docs.str().find("`" + p.key), std::string::npos)
          << e.name << "'s " << p.key << " in the docs";
  }
  EXPECT_EQ(usage(*find_balancer("queue")), "queue[:tile=64][:batch=1][:pipeline=paper]");
}

// The worked example of docs/design-notes.md: a balancer added by one registration.
class Halves : public Balancer {
 public:
  Halves(int n, Layout layout) : even_(n, layout) {}
  std::string name() const override { return "toy-halves"; }
  Plan plan(const FrameShape& shape, int frame) override { return even_.plan(shape, frame); }
  void update(const FrameStats& stats) override { even_.update(stats); }
  void drop_device(int index) override { even_.drop_device(index); }

 private:
  UniformBalancer even_;
};

TEST(Registry, AToyBalancerIsAddedByOneRegistration) {
  register_balancer(
      {"toy-halves",
       "an even split, registered by a test",
       "ours",
       {{"layout", "rows", "rows|columns", "how the halves are laid out"}},
       [](Spec& s, int n) {
         const bool columns = s.get_string("layout", "rows", {"rows", "columns"}) == "columns";
         return std::make_unique<Halves>(n, columns ? Layout::Columns : Layout::Rows);
       }});
  const auto b = make_balancer("toy-halves:layout=columns", 2);
  EXPECT_EQ(b->name(), "toy-halves");
  const Plan plan = b->plan(FrameShape{64, 32, 1, {}, {}}, 0);
  ASSERT_EQ(plan.assigned.size(), 2u);
  EXPECT_EQ(plan.assigned[0].at(0).rect.x1, 32);  // columns: the left half
  EXPECT_EQ(balancer_names().back(), "toy-halves");
  EXPECT_NE(balancer_help().find("toy-halves[:layout=rows]"), std::string::npos);
  EXPECT_THROW(make_balancer("toy-halves:tile=3", 2), std::invalid_argument);
  EXPECT_THROW(
      register_balancer({"toy-halves",
                         "again",
                         "ours",
                         {},
                         [](Spec&, int n) { return std::make_unique<Halves>(n, Layout::Rows); }}),
      std::invalid_argument);
  EXPECT_THROW(register_balancer({"", "", "", {}, nullptr}), std::invalid_argument);
}

// Names follow the CLI's grammar (letters, digits, '-', '_'): a newline made a trace its
// own reader refused (bench writes "balancer NAME"), a comma split balancer lists, a ':'
// or '=' reads as options. Refused, whoever registers.
TEST(Registry, ANameOutsideTheGrammarIsRefused) {
  const auto make = [](Spec&, int n) { return std::make_unique<Halves>(n, Layout::Rows); };
  for (const std::string bad :
       {"two\nlines", "a,b", "a:b", "a=b", "a b", "tab\t", "caf\xc3\xa9", "dot.ted", "slash/ed"}) {
    EXPECT_THROW(register_balancer({bad, "bad", "ours", {}, make}), std::invalid_argument) << bad;
    EXPECT_EQ(find_balancer(bad), nullptr) << bad;
  }
  register_balancer({"Toy_rows-2", "good", "ours", {}, make});
  EXPECT_NE(find_balancer("Toy_rows-2"), nullptr);
}

}  // namespace registry_test
}  // namespace multiray::balance
