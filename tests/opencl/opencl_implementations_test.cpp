// One image on every OpenCL implementation: the kernels are written for drivers we cannot
// run (NVIDIA, AMD, Intel), so each implementation this machine has (PoCL, Mesa's rusticl
// on llvmpipe, ...) renders the same frames through the multiray binary, each alone in its
// process (OCL_ICD_VENDORS names its ICD file), and the images must agree bit for bit:
// the path tracer flat and compact, with adaptive and reprojected sampling, and the
// volume raycaster. Each render's hash (stats.json) is a hash of its float pixels.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "core/image.h"
#include "support/run_cli.h"

namespace multiray {
namespace opencl_implementations_test {

#ifdef MULTIRAY_BIN
namespace fs = std::filesystem;

// The volume raycaster's largest difference between implementations, per channel of a
// pixel (radiance in [0, 1]). Its opacity is -expm1(log transparency x step ratio)
// (render/shared/transfer.h), and OpenCL C 1.2 allows expm1 an error of 3 ulp, which each
// implementation's library spends differently (PoCL's and Mesa's libclc differ in the last
// bit); a ray composites many samples, so a pixel may drift by a few ulp. Measured
// 2026-12-03, PoCL 3.1 against rusticl (Mesa 22.3.6): at most 2.98e-8 (one ulp of a value
// in [0.25, 0.5)). 1e-6 leaves room for other libraries and is still far below what a
// wrong step, block or sample gives (and below an 8-bit PNG step, 4e-3).
constexpr float kVolumeTolerance = 1e-6f;

// An implementation: its ICD file and the name of its first device.
struct Implementation {
  std::string icd, device;
};

// The environment that makes `icd` the only OpenCL implementation of a process, with
// rusticl's llvmpipe device enabled on one thread (no effect on other implementations).
std::string env_for(const std::string& icd) {
  return "OCL_ICD_VENDORS='" + icd + "' RUSTICL_ENABLE=llvmpipe LP_NUM_THREADS=1";
}

// Every ICD file of /etc/OpenCL/vendors through which multiray finds a device.
std::vector<Implementation> implementations() {
  std::vector<Implementation> out;
  std::error_code ec;
  std::vector<std::string> icds;
  for (const auto& e : fs::directory_iterator("/etc/OpenCL/vendors", ec))
    if (e.path().extension() == ".icd") icds.push_back(e.path().string());
  std::sort(icds.begin(), icds.end());
  for (const std::string& icd : icds) {
    const testing::CliResult r = testing::run_cli(MULTIRAY_BIN, "devices", env_for(icd));
    std::istringstream lines(r.out);
    for (std::string line; std::getline(lines, line);)
      if (line.rfind("opencl ", 0) == 0 && line.find("opencl:0") != std::string::npos) {
        const size_t from = line.find_first_not_of(' ', 6);
        out.push_back({icd, line.substr(from, line.find("  ", from) - from)});
        break;
      }
  }
  return out;
}

// The "image_hash" of every frame in <out>/stats.json, in order.
std::string hashes(const std::string& out) {
  std::ifstream in(out + "/stats.json");
  std::stringstream text;
  text << in.rdbuf();
  const std::string s = text.str();
  std::string all;
  for (size_t at = s.find("\"image_hash\""); at != std::string::npos;
       at = s.find("\"image_hash\"", at + 1)) {
    const size_t q = s.find('"', s.find(':', at));
    all += s.substr(q + 1, 16) + " ";
  }
  return all;
}

// A 16^3 uint8 raw volume: a ball of 200 in a ramp.
std::string ball_raw() {
  const std::string path = ::testing::TempDir() + "/multiray_impl_ball.raw";
  std::string bytes;
  for (int z = 0; z < 16; ++z)
    for (int y = 0; y < 16; ++y)
      for (int x = 0; x < 16; ++x) {
        const int dx = x - 8, dy = y - 8, dz = z - 8;
        bytes.push_back(char(dx * dx + dy * dy + dz * dz < 30 ? 200 : 4 * x));
      }
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

// Each case: its render arguments (the devices come last) and the device keys. The
// `wg=7:tile=9` cases are the default ones again with another launch shape: the pixels
// must not change. `exact`: bit for bit across implementations; else to VOLUME_TOLERANCE.
struct Case {
  std::string name, args, keys;
  bool exact = true;
};
std::vector<Case> cases() {
  const std::string common = "--res 24x16 --spp 2 --frames 2 --camera-path orbit:8";
  const std::string volume = "render " + ball_raw() +
                             " --raw 16x16x16:uint8 --tf grey --res 24x16 --frames 2 "
                             "--camera-path orbit:8 --exr";
  return {{"path", "render " + common, ""},
          {"path wg=7", "render " + common, ":wg=7:tile=9"},
          {"path compact", "render " + common, ":compact=1"},
          {"adaptive", "render " + common + " --sampling adaptive --edge-spp 3", ""},
          {"reproject", "render " + common + " --views 3x1 --sampling reproject", ""},
          {"volume", volume, "", false},
          {"volume wg=7", volume, ":wg=7:tile=9", false}};
}

TEST(OpenClImplementations, EveryKernelGivesTheSameImageOnEveryImplementation) {
  const std::vector<Implementation> found = implementations();
  if (found.size() < 2) {
    std::string names;
    for (const Implementation& i : found) names += " " + i.device;
    GTEST_SKIP() << "found " << found.size() << " OpenCL implementation(s):" << names
                 << "; install pocl-opencl-icd and mesa-opencl-icd (rusticl) to compare two";
  }
  const std::string out = ::testing::TempDir() + "/multiray_impl";
  // case name -> implementation -> hashes of its frames
  std::map<std::string, std::map<std::string, std::string>> seen;
  std::map<std::string, std::map<std::string, Framebuffer>> images;  // of the inexact cases
  for (const Case& c : cases())
    for (const Implementation& impl : found) {
      fs::remove_all(out);
      const testing::CliResult r = testing::run_cli(
          MULTIRAY_BIN, c.args + " -q --out " + out + " --devices opencl:0" + c.keys,
          env_for(impl.icd));
      ASSERT_EQ(r.code, 0) << c.name << " on " << impl.device << ":\n" << r.out;
      seen[c.name][impl.device] = hashes(out);
      if (!c.exact) images[c.name][impl.device] = read_exr(out + "/frame_0001.exr");
      EXPECT_FALSE(seen[c.name][impl.device].empty()) << c.name << ": no image_hash in stats.json";
    }
  fs::remove_all(out);
  for (const auto& [name, by_impl] : seen)
    for (const auto& [device, h] : by_impl)
      if (images.count(name) == 0) {
        EXPECT_EQ(h, by_impl.begin()->second)
            << name << ": " << device << " against " << by_impl.begin()->first;
      }
  for (const auto& [name, by_impl] : images)
    for (const auto& [device, image] : by_impl) {
      const Framebuffer& first = by_impl.begin()->second;
      ASSERT_EQ(image.pixels.size(), first.pixels.size());
      float worst = 0;
      for (size_t i = 0; i < image.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c)
          worst = std::max(worst, std::abs(image.pixels[i][c] - first.pixels[i][c]));
      EXPECT_LE(worst, kVolumeTolerance)
          << name << ": " << device << " against " << by_impl.begin()->first;
      std::printf("%s, %s against %s: largest difference %.3g\n", name.c_str(), device.c_str(),
                  by_impl.begin()->first.c_str(), double(worst));
    }
  // Another work-group size and tile change no pixel.
  EXPECT_EQ(seen["path wg=7"], seen["path"]);
  EXPECT_EQ(seen["volume wg=7"], seen["volume"]);
}
#endif

}  // namespace opencl_implementations_test
}  // namespace multiray
