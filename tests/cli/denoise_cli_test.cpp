// --denoise through the command line (issue 52): the PNG shows the denoised image, the
// same bits whichever balancer and devices split the frame; auto is off at 256 spp and
// where the run records no feature buffers; an EXR keeps the raw beauty unless a method
// is named; bad values and impossible combinations are refused in one line.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "core/image.h"
#include "support/cli_expect.h"

namespace denoise_cli_test {

using Result = multiray::testing::CliResult;

Result run(const std::string& args) { return multiray::testing::run_cli(MULTIRAY_BIN, args); }

std::string folder(const std::string& name) {
  const std::string dir = ::testing::TempDir() + "/denoise_cli_" + name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

std::string bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

const std::string kSmall = "render --res 64x36 --spp 4 --seed 3 -q ";

TEST(DenoiseCli, ThePngIsDenoisedTheSameWhateverTheSplit) {
  const std::string d = folder("split");
  ASSERT_EQ(run(kSmall + "--denoise none -o " + d + "/raw.png").code, 0);
  ASSERT_EQ(run(kSmall + "--devices cpu:threads=1 -o " + d + "/one.png").code, 0);
  ASSERT_EQ(
      run(kSmall + "--devices cpu:threads=1,cpu:threads=1 --balancer queue -o " + d + "/two.png")
          .code,
      0);
  ASSERT_EQ(run(kSmall +
                "--devices cpu:threads=1,cpu:threads=1,cpu:threads=1 --balancer "
                "dlb -o " +
                d + "/three.png")
                .code,
            0);
  EXPECT_NE(bytes(d + "/raw.png"), bytes(d + "/one.png"));  // auto denoised it
  EXPECT_EQ(bytes(d + "/one.png"), bytes(d + "/two.png"));
  EXPECT_EQ(bytes(d + "/one.png"), bytes(d + "/three.png"));
  // Its time is in stats.json, apart from the frame's.
  EXPECT_THAT(bytes(d + "/one.stats.json"), ::testing::ContainsRegex("\"denoise_ms\": *[0-9]"));
  EXPECT_THAT(bytes(d + "/raw.stats.json"), ::testing::HasSubstr("\"denoise_ms\": 0"));
}

TEST(DenoiseCli, SvgfsHistoryIsTheSameWhateverTheSplit) {
  const std::string d = folder("svgf");
  const std::string orbit =
      "render --res 48x27 --spp 2 -q --frames 3 --camera-path orbit:12 "
      "--denoise svgf ";
  ASSERT_EQ(run(orbit + "--devices cpu:threads=1 -o " + d + "/one_#.png").code, 0);
  ASSERT_EQ(
      run(orbit + "--devices cpu:threads=1,cpu:threads=1 --balancer hybrid -o " + d + "/two_#.png")
          .code,
      0);
  for (const char* f : {"0", "2"})
    EXPECT_EQ(bytes(d + "/one_" + f + ".png"), bytes(d + "/two_" + f + ".png")) << f;
}

// Frame N filtered while frame N+1 renders (the default) or before it: the same frames.
TEST(DenoiseCli, FilteringBesideTheNextFrameGivesTheSameFrames) {
  const std::string d = folder("overlap");
  const std::string orbit =
      "render --res 48x27 --spp 2 -q --frames 4 --camera-path orbit:12 --denoise svgf ";
  ASSERT_EQ(run(orbit + "-o " + d + "/beside_#.png").code, 0);
  ASSERT_EQ(run(orbit + "--no-denoise-overlap -o " + d + "/before_#.png").code, 0);
  for (const char* f : {"0", "1", "2", "3"}) {
    EXPECT_FALSE(bytes(d + "/beside_" + f + ".png").empty()) << f;
    EXPECT_EQ(bytes(d + "/beside_" + f + ".png"), bytes(d + "/before_" + f + ".png")) << f;
  }
}

TEST(DenoiseCli, AutoIsOffAt256SamplesAndWhereNoFeaturesAreRecorded) {
  const std::string d = folder("auto");
  const std::string many = "render --res 24x16 --spp 256 --seed 3 -q ";
  ASSERT_EQ(run(many + "-o " + d + "/auto.png").code, 0);
  ASSERT_EQ(run(many + "--denoise none -o " + d + "/none.png").code, 0);
  EXPECT_EQ(bytes(d + "/auto.png"), bytes(d + "/none.png"));
  const std::string ao = "render --res 24x16 --spp 4 --integrator ao -q ";
  ASSERT_EQ(run(ao + "-o " + d + "/ao_auto.png").code, 0);
  ASSERT_EQ(run(ao + "--denoise none -o " + d + "/ao_none.png").code, 0);
  EXPECT_EQ(bytes(d + "/ao_auto.png"), bytes(d + "/ao_none.png"));
}

TEST(DenoiseCli, TheExrKeepsTheRawBeautyUnlessAMethodIsNamed) {
  const std::string d = folder("exr");
  ASSERT_EQ(run(kSmall + "--exr --denoise none -o " + d + "/none.png").code, 0);
  ASSERT_EQ(run(kSmall + "--exr -o " + d + "/auto.png").code, 0);
  ASSERT_EQ(run(kSmall + "--exr --denoise atrous -o " + d + "/named.png").code, 0);
  const uint64_t raw = multiray::image_hash(multiray::read_exr(d + "/none.exr"));
  EXPECT_EQ(multiray::image_hash(multiray::read_exr(d + "/auto.exr")), raw);
  EXPECT_NE(multiray::image_hash(multiray::read_exr(d + "/named.exr")), raw);
  EXPECT_NE(bytes(d + "/auto.png"), bytes(d + "/none.png"));
}

// --denoise-normal svgf, the papers' normal term, reaches the filter: the box's ball is
// curved, so its image differs from the default term's; both the same whatever the split.
TEST(DenoiseCli, ThePapersNormalTermIsSelectable) {
  const std::string d = folder("normal");
  const std::string a = kSmall + "--denoise atrous ";
  ASSERT_EQ(run(a + "-o " + d + "/turn.png").code, 0);
  ASSERT_EQ(run(a + "--denoise-normal svgf -o " + d + "/svgf.png").code, 0);
  ASSERT_EQ(run(a +
                "--denoise-normal svgf --devices cpu:threads=1,cpu:threads=1 --balancer "
                "queue -o " +
                d + "/svgf_two.png")
                .code,
            0);
  EXPECT_NE(bytes(d + "/turn.png"), bytes(d + "/svgf.png"));
  EXPECT_EQ(bytes(d + "/svgf.png"), bytes(d + "/svgf_two.png"));
}

// --svgf-history accumulated (ours until 2026-12-04) reaches svgf: from the second frame
// on its history differs from the paper's filtered one, so the frames differ.
TEST(DenoiseCli, SvgfsHistoryFormIsSelectable) {
  const std::string d = folder("history");
  const std::string a = kSmall + "--denoise svgf --frames 2 --camera-path orbit ";
  ASSERT_EQ(run(a + "-o " + d + "/filtered_#.png").code, 0);
  ASSERT_EQ(run(a + "--svgf-history accumulated -o " + d + "/accumulated_#.png").code, 0);
  EXPECT_EQ(bytes(d + "/filtered_0.png"), bytes(d + "/accumulated_0.png"));  // no history yet
  EXPECT_NE(bytes(d + "/filtered_1.png"), bytes(d + "/accumulated_1.png"));
}

TEST(DenoiseCli, BadValuesAreRefusedInOneLine) {
  const std::string d = folder("bad");
  const std::string c = "render --res 8x8 --denoise-normal cosine -o " + d + "/x.png";
  multiray::testing::expect_input_error(run(c), c, "must be turn or svgf");
  const std::string h = "render --res 8x8 --svgf-history raw -o " + d + "/x.png";
  multiray::testing::expect_input_error(run(h), h, "must be filtered or accumulated");
  const std::string a = "render --res 8x8 --denoise atros -o " + d + "/x.png";
  multiray::testing::expect_input_error(run(a), a, "did you mean atrous");
  const std::string b = "render --res 8x8 --integrator ao --denoise svgf -o " + d + "/x.png";
  multiray::testing::expect_input_error(run(b), b, "--denoise");
}

}  // namespace denoise_cli_test
