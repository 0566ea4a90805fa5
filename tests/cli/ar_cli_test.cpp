// Augmented reality through the command line (docs/ar.md): the example's composite against a
// full render of the same scene, the real image kept where no object reaches, the RGBA
// layer, and bad input refused in one line.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <stb_image.h>
#include <unistd.h>

#include "core/composite.h"
#include "support/cli_expect.h"

namespace ar_cli_test {

using multiray::Framebuffer;
using multiray::testing::CliResult;
using multiray::testing::expect_input_error;
using multiray::testing::temp_file;

CliResult run(const std::string& args) { return multiray::testing::run_cli(MULTIRAY_BIN, args); }

const std::string kExample = std::string(MULTIRAY_SOURCE_DIR) + "/examples/ar";

// The example's script at a small size, once per test process; returns its folder.
const std::string& example_output() {
  static const std::string dir = [] {
    // This process's own: ctest runs each test in a process of its own, concurrently.
    const std::string d = ::testing::TempDir() + "/ar_cli_example_" + std::to_string(getpid());
    std::filesystem::remove_all(d);
    const std::string cmd = "MULTIRAY='" + std::string(MULTIRAY_BIN) +
                            "' RES=160x120 SPP=16 FRAMES=3 sh '" + kExample + "/run.sh' '" + d +
                            "' > /dev/null 2>&1";
    EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
    return d;
  }();
  return dir;
}

// The largest difference of mean luminance over 8x8 blocks: noise averages out in a block
// (by 8x), a missing or misplaced shadow does not.
double max_block_difference(const Framebuffer& a, const Framebuffer& b) {
  double worst = 0;
  for (int by = 0; by + 8 <= a.height; by += 8)
    for (int bx = 0; bx + 8 <= a.width; bx += 8) {
      double d = 0;
      for (int y = by; y < by + 8; ++y)
        for (int x = bx; x < bx + 8; ++x) d += multiray::luminance(a.at(x, y) - b.at(x, y));
      worst = std::max(worst, std::abs(d / 64));
    }
  return worst;
}

Framebuffer frame(const std::string& name) {
  return multiray::read_image_linear(example_output() + "/" + name);
}

// The composite against the ground and objects rendered together: they differ by no more
// than two independent renders of that scene do (the tolerance is the renderer's own noise,
// measured on the spot), and a composite without the shadows would not pass.
TEST(ArCli, CompositeAgreesWithAFullRenderUpToNoise) {
  const std::string out = example_output();
  const std::string again = out + "/again";  // within this process's folder
  const CliResult r =
      run("render '" + kExample + "/ground_and_objects.obj' --poses '" + kExample +
          "/poses.json' --frames 3 --res 160x120 --spp 16 --env 0.3 --sun 40,35 -q --seed 2 "
          "--exposure 0 --tone clamp --denoise none -o '" +
          again + "/ref_####.png'");
  ASSERT_EQ(r.code, 0) << r.out;
  for (const char* f : {"0000", "0002"}) {
    const Framebuffer ref = frame(std::string("ref_") + f + ".png");
    const Framebuffer ref2 = multiray::read_image_linear(again + "/ref_" + f + ".png");
    const Framebuffer ar = frame(std::string("ar_") + f + ".png");
    const Framebuffer bg = frame(std::string("bg_") + f + ".png");
    const double noise = max_block_difference(ref2, ref);
    EXPECT_LE(max_block_difference(ar, ref), 1.5 * noise) << "frame " << f;
    EXPECT_GT(max_block_difference(bg, ref), 3.0 * noise) << "frame " << f;  // objects matter
  }
}

// Where no virtual object reaches (the sky, most of the ground) the real image comes out
// exactly as it went in; the layer is transparent there and opaque on the objects.
TEST(ArCli, TheRealImageIsKeptWhereNoObjectReaches) {
  const std::string out = example_output();
  int w = 0, h = 0, n = 0;
  unsigned char* ar = stbi_load((out + "/ar_0001.png").c_str(), &w, &h, &n, 3);
  unsigned char* bg = stbi_load((out + "/bg_0001.png").c_str(), &w, &h, &n, 3);
  unsigned char* layer = stbi_load((out + "/ar_0001_rgba.png").c_str(), &w, &h, &n, 0);
  ASSERT_TRUE(ar && bg && layer);
  EXPECT_EQ(n, 4);
  size_t same = 0, clear = 0;
  for (int i = 0; i < w * h; ++i) {
    const bool kept =
        ar[3 * i] == bg[3 * i] && ar[3 * i + 1] == bg[3 * i + 1] && ar[3 * i + 2] == bg[3 * i + 2];
    same += kept;
    if (layer[4 * i + 3] == 0) {
      ++clear;
      EXPECT_TRUE(kept) << "pixel " << i % w << "," << i / w;
    }
  }
  EXPECT_GT(clear, size_t(w * h / 2));
  EXPECT_GE(same, clear);
  EXPECT_EQ(layer[4 * ((h / 2) * w + w / 2) + 3], 255);  // the sphere, in the middle
  stbi_image_free(ar), stbi_image_free(bg), stbi_image_free(layer);
}

// A PNG of 4x3 pixels whose header claims `width` x `height`: what a 560 KB file of one
// colour claiming 16000x12000 looks like to a check that reads headers only.
std::string png_claiming(const std::string& name, uint32_t width, uint32_t height) {
  std::string png = multiray::encode_png_rgba(4, 3, std::vector<uint8_t>(4 * 3 * 4, 128));
  for (int i = 0; i < 4; ++i) {  // IHDR's width and height, big-endian, at bytes 16 and 20
    png[size_t(16 + i)] = char((width >> (24 - 8 * i)) & 0xff);
    png[size_t(20 + i)] = char((height >> (24 - 8 * i)) & 0xff);
  }
  return temp_file(name, png);
}

// Backgrounds are charged against --max-memory from their headers before anything
// renders, the largest frame of a numbered sequence included (issue 53).
TEST(ArCli, BackgroundsAreChargedAgainstMaxMemory) {
  const std::string huge = png_claiming("huge.png", 16000, 12000);
  temp_file("seq_0000.png",
            multiray::encode_png_rgba(160, 120, std::vector<uint8_t>(160 * 120 * 4, 128)));
  const std::string seq = png_claiming("seq_0001.png", 16000, 12000);
  const std::string base = "render '" + kExample + "/objects.obj' --spp 1 -q --res 160x120 -o " +
                           example_output() + "/mem --overwrite --env 0.3 --ground y=0 ";
  for (const std::string& bg : {huge, seq.substr(0, seq.size() - 8) + "####.png"}) {
    const std::string args = "--max-memory 1G --frames 2 --background '" + bg + "'";
    const CliResult r = run(base + args);
    expect_input_error(r, args, "--max-memory");
    EXPECT_THAT(r.out, ::testing::HasSubstr(bg == huge ? huge : seq)) << args;
    EXPECT_THAT(r.out, ::testing::HasSubstr("16000 x 12000 pixels")) << args;
  }
  // The same sequence within a limit that holds it renders.
  EXPECT_EQ(run(base + "--frames 1 --max-memory 1G --background '" +
                seq.substr(0, seq.size() - 8) + "####.png'")
                .code,
            0);
}

TEST(ArCli, BadInputIsRefusedInOneLine) {
  const std::string obj = kExample + "/objects.obj", poses = kExample + "/poses.json";
  const std::string bg = example_output() + "/bg_####.png";
  const std::string base =
      "render '" + obj + "' --spp 1 -q -o " + example_output() + "/bad --overwrite --env 0.3 ";
  const std::string wide =
      temp_file("wide.json", R"({"image":[200,100],"intrinsics":[100,100,100,50],
    "poses":[{"transform":[1,0,0,0, 0,1,0,0, 0,0,1,0, 0,1,5,1]}]})");
  const std::string skew =
      temp_file("skew.json", R"({"image":[160,120],"intrinsics":[100,100,80,60],
    "poses":[{"transform":[1,0,0,0, 0,2,0,0, 0,0,1,0, 0,1,5,1]}]})");
  const std::string tele =
      temp_file("tele.json", R"({"image":[160,120],"intrinsics":[1e30,1e30,80,60],
    "poses":[{"transform":[1,0,0,0, 0,1,0,0, 0,0,1,0, 0,1,5,1]}]})");
  const std::pair<std::string, std::string> cases[] = {
      {"--background " + bg, "--background needs --ground"},
      {"--ground y", "--ground"},
      {"--ground w=0", "--ground"},
      {"--ground y=0,albedo=2", "albedo"},
      {"--ground y=nan", "--ground"},
      {"--ground y=0 --integrator ao", "--integrator ao"},
      {"--ground y=0 --views 2x1", "--views"},
      {"--ground y=0 --devices cpu,opencl", "opencl"},  // CPU only (or: built without OpenCL)
      {"--ground y=0 --env 0 --sun off", "--env"},
      {"--ground y=0 --background '" + example_output() + "/bg_#####.png'", "does not exist"},
      {"--ground y=0 --res 100x100 --background '" + bg + "'", "aspect ratio"},
      {"--poses '" + wide + "'", "aspect ratio"},
      {"--poses '" + skew + "'", "not a rotation"},
      {"--poses '" + poses + "' --camera-path orbit", "both move the camera"},
      {"--poses '" + poses + "' --frames 9", "--frames 9 is more than the 8 poses"},
      {"--poses '" + tele + "'", "field of view"},
      {"--poses /nonexistent.json", "--poses"},
      {"--poses '" + obj + "'", "not valid JSON"},
  };
  for (const auto& [args, word] : cases) {
    const std::string res = args.find("--res") == std::string::npos ? " --res 160x120" : "";
    expect_input_error(run(base + args + res), args, word);
  }
}

}  // namespace ar_cli_test
