// The golden image cases: what the test renders and what golden_record recorded. Changing
// a case's arguments means recording it again (tests/golden/README.md).
#pragma once

#include <string>
#include <vector>

namespace multiray::testing {

struct GoldenCase {
  std::string name;   // also the folder tests/golden/<name>/
  std::string scene;  // relative to the shared data folder; empty: the built-in scene
  std::string args;   // render options (no --seed, --devices, --balancer or --out)
};

inline const std::vector<GoldenCase>& golden_cases() {
  static const std::vector<GoldenCase> cases = {
      {"default", "", "--res 64x40 --spp 16 --frames 2 --camera-path orbit:8"},
      {"ao", "",
       "--res 48x32 --frames 2 --camera-path orbit:8 --integrator ao --sampling adaptive"},
      {"views", "",
       "--res 32x20 --spp 16 --frames 2 --views 2x2 --view-spacing 0.2 --camera-path orbit:8"},
      {"foveated", "",
       "--res 64x40 --frames 2 --camera-path orbit:8 --integrator ao --sampling foveated "
       "--fovea-spp 16 --periphery-spp 0.5"},
      // Sponza's default view from outside until issue 32 (the default is now inside),
      // pinned so that the recorded reference still holds.
      {"sponza", "meshes/dabrovic_sponza/sponza.obj",
       "--res 64x40 --spp 8 --frames 2 --camera-path orbit:8 --camera "
       "25.580339431762695,28.163795471191406,36.523651123046875,0.00724029541015625,7."
       "3733110427856445,0.0014879703521728516,0,1,0,45"},
  };
  return cases;
}

inline const GoldenCase* find_golden_case(const std::string& name) {
  for (const GoldenCase& c : golden_cases())
    if (c.name == name) return &c;
  return nullptr;
}

}  // namespace multiray::testing
