// The device backend registry (device/device_factory.h) against the factory: every key a
// backend lists is accepted and no other, and every numeric range its help states is the
// range the factory enforces (both ends accepted, one step outside refused). The help
// (--devices, `multiray devices`) is printed from the registry, so it cannot go stale; the
// page docs/devices.md is checked against it.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <optional>
#include <sstream>
#include <string>

#include "core/error.h"
#include "device/device_factory.h"
#include "util/parse.h"

namespace multiray {
namespace {

bool accepted(const std::string& text) {
  try {
    parse_device_specs(text);
    return true;
  } catch (const InputError&) {
    return false;
  }
}

struct Range {
  double lo, hi;
  bool lo_open, whole;
};

// "1..1024" (whole numbers), "[0.01, 1]" or "(0, 1]"; nullopt for other forms ("0, 0+2").
std::optional<Range> numeric_range(const std::string& values) {
  if (const size_t dots = values.find(".."); dots != std::string::npos) {
    const auto lo = parse_number(values.substr(0, dots));
    const auto hi = parse_number(values.substr(dots + 2));
    if (lo && hi) return Range{*lo, *hi, false, true};
    return std::nullopt;
  }
  const size_t comma = values.find(", ");
  if (values.size() < 5 || comma == std::string::npos || values.back() != ']') return std::nullopt;
  const auto lo = parse_number(values.substr(1, comma - 1));
  const auto hi = parse_number(values.substr(comma + 2, values.size() - comma - 3));
  if (!lo || !hi) return std::nullopt;
  return Range{*lo, *hi, values.front() == '(', false};
}

std::string num(double v) {
  std::string s = std::to_string(v);
  s.erase(s.find_last_not_of('0') + 1);
  if (s.back() == '.') s.pop_back();
  return s;
}

TEST(DeviceRegistry, EveryStatedRangeIsTheEnforcedOne) {
  int ranges = 0;
  for (const BackendEntry& b : device_backends())
    for (const BackendParam& p : b.built ? b.params : std::vector<BackendParam>{}) {
      const auto r = numeric_range(p.values);
      if (!r) continue;
      ++ranges;
      const std::string at = b.name + ":" + p.key + "=";
      const double step = r->whole ? 1 : (r->hi - r->lo) * 1e-3;
      EXPECT_TRUE(accepted(at + num(r->hi))) << at << num(r->hi) << " (" << p.values << ")";
      EXPECT_FALSE(accepted(at + num(r->hi + step))) << at << num(r->hi + step);
      if (r->lo_open) {
        EXPECT_FALSE(accepted(at + num(r->lo))) << at << num(r->lo) << " (" << p.values << ")";
        EXPECT_TRUE(accepted(at + num(r->lo + step))) << at << num(r->lo + step);
      } else {
        EXPECT_TRUE(accepted(at + num(r->lo))) << at << num(r->lo) << " (" << p.values << ")";
        EXPECT_FALSE(accepted(at + num(r->lo - step))) << at << num(r->lo - step);
      }
    }
  EXPECT_GE(ranges, 5);  // threads, speed, quota, tile, ... on the CPU alone
}

TEST(DeviceRegistry, EveryListedKeyIsTakenAndNoOther) {
  for (const BackendEntry& b : device_backends()) {
    if (!b.built) continue;  // refused whole: NotBuiltBackendsAreListedAndSayHowToBuildThem
    for (const BackendParam& p : b.params) {
      // Present but with an empty value: refused for its value, never as an unknown key.
      try {
        parse_device_specs(b.name + ":" + p.key + "=");
      } catch (const InputError& e) {
        EXPECT_THAT(e.what(), ::testing::Not(::testing::HasSubstr("unknown"))) << p.key;
      }
    }
    try {
      parse_device_specs(b.name + ":bogus=1");
      ADD_FAILURE() << b.name << " took an unlisted key";
    } catch (const InputError& e) {
      for (const BackendParam& p : b.params)
        EXPECT_THAT(e.what(), ::testing::HasSubstr(p.key)) << "the error lists the keys";
    }
  }
}

// docs/devices.md names every backend, every key (in a table row) and every kernel.
TEST(DeviceRegistry, TheDocsNameEveryBackendKeyAndKernel) {
  std::ifstream in(std::string(MULTIRAY_SOURCE_DIR) + "/docs/devices.md");
  ASSERT_TRUE(in) << "docs/devices.md";
  std::stringstream text;
  text << in.rdbuf();
  const std::string docs = text.str();
  for (const BackendEntry& b : device_backends()) {
    const size_t section = docs.find("## `" + b.name + "`");
    ASSERT_NE(section, std::string::npos) << b.name;
    const size_t end = docs.find("\n## ", section + 1);
    const std::string part = docs.substr(section, end - section);
    for (const BackendParam& p : b.params)
      EXPECT_NE(part.find("| `" + p.key + "` | " + p.values + " |"), std::string::npos)
          << b.name << "'s " << p.key << " (" << p.values << ") in docs/devices.md";
    for (const std::string& k : backend_capabilities(b.name).kernels)
      EXPECT_NE(part.find("`" + k + "`"), std::string::npos) << b.name << "'s kernel " << k;
  }
}

TEST(DeviceRegistry, UnknownTypesAreRefusedNamingTheKnownOnes) {
  try {
    parse_device_specs("gpu");
    ADD_FAILURE();
  } catch (const InputError& e) {
    for (const BackendEntry& b : device_backends())
      EXPECT_THAT(e.what(), ::testing::HasSubstr(b.name));
  }
  ASSERT_NE(find_backend("cpu"), nullptr);
  EXPECT_FALSE(backend_capabilities("cpu").kernels.empty());
  EXPECT_TRUE(backend_capabilities("gpu").kernels.empty());
}

// A backend this multiray was built without stays in the registry (help, `multiray
// devices`), without capabilities, and a spec naming it is refused saying how to build it.
TEST(DeviceRegistry, NotBuiltBackendsAreListedAndSayHowToBuildThem) {
  for (const BackendEntry& b : device_backends()) {
    EXPECT_EQ(b.built, b.capabilities != nullptr && b.create != nullptr) << b.name;
    if (b.built) continue;
    EXPECT_TRUE(backend_capabilities(b.name).kernels.empty()) << b.name;
    try {
      parse_device_specs(b.name);
      ADD_FAILURE() << b.name << " is not built but was accepted";
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), ::testing::HasSubstr(b.not_built));
    }
  }
}

}  // namespace
}  // namespace multiray
