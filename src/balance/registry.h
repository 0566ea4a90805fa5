// The balancer registry: every balancer make_balancer() can build, with the one-line help,
// the credit and the parameters (default and range) that `--help`, the docs check and the
// contract tests are generated from or checked against, so no list of balancers is kept
// by hand anywhere else.
//
// Adding a balancer: write its class (balance/x.h, x.cpp), then one entry in
// builtin_balancers() (registry.cpp); a renderer that links the library can add its own
// with register_balancer() (docs/design-notes.md shows a worked example).
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "balance/balancer.h"
#include "util/spec.h"

namespace multiray::balance {

// One option of a balancer spec, as written in help and docs.
struct ParamInfo {
  std::string key;
  std::string fallback;  // the default, as written in a spec ("64", "auto", "rows")
  std::string values;    // the range or the choices ("1..4096", "rows|columns", "A/B/...")
  std::string help;      // one line
};

struct BalancerEntry {
  std::string name;    // as in a spec
  std::string help;    // one line
  std::string credit;  // the method's source (title, section) or "ours"
  std::vector<ParamInfo> params;
  // Builds it for `device_count` devices, reading its options from `spec` with the typed
  // getters (the defaults and ranges there are the ones `params` states; a test holds
  // them to it). Throws std::invalid_argument through `spec` for a bad option.
  std::function<std::unique_ptr<Balancer>(Spec& spec, int device_count)> make;
};

// Every registered balancer: the built-in ones in the order of DESIGN.md, the peers'
// balancers, then those added by register_balancer().
const std::vector<BalancerEntry>& balancer_registry();

// True for a name a spec and a list of specs can carry: one or more ASCII letters, digits,
// '-' and '_' (the CLI's grammar; no ':', '=', ',', space or newline).
bool valid_balancer_name(const std::string& name);

// Adds a balancer. Throws std::invalid_argument for a name that is not valid_balancer_name()
// or already registered, or a missing factory. Not thread-safe: register before building
// balancers concurrently.
void register_balancer(BalancerEntry entry);

// The entry called `name`, or nullptr.
const BalancerEntry* find_balancer(const std::string& name);

// "queue[:tile=64][:batch=1][:pipeline=paper]": the name with every option and its default.
std::string usage(const BalancerEntry& e);

// Every balancer's usage and help, one per line, for `--help` ("  queue[:tile=64]...  a
// shared queue of tiles ...").
std::string balancer_help();

}  // namespace multiray::balance
