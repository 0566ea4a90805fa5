#include "balance/balancer.h"

#include "balance/registry.h"
#include "util/spec.h"

namespace multiray::balance {

std::vector<std::string> balancer_names() {
  std::vector<std::string> names;
  for (const BalancerEntry& e : balancer_registry()) names.push_back(e.name);
  return names;
}

std::unique_ptr<Balancer> make_balancer(const std::string& text, int device_count) {
  Spec spec(text);
  if (device_count < 1 || device_count > 4096)
    spec.fail("device count " + std::to_string(device_count) + " is outside 1..4096");
  const BalancerEntry* entry = find_balancer(spec.name());
  if (!entry) {
    std::string known;
    for (const std::string& b : balancer_names()) known += (known.empty() ? "" : ", ") + b;
    spec.fail("unknown balancer '" + spec.name() + "' (known: " + known + ")");
  }
  std::unique_ptr<Balancer> balancer = entry->make(spec, device_count);
  spec.finish();
  return balancer;
}

}  // namespace multiray::balance
