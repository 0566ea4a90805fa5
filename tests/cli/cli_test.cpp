// The multiray command line, run as a user would: bad input gets one clear line on stderr
// and a non-zero exit, never a crash or a hang; good input writes images and stats.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "support/cli_expect.h"

namespace cli_test {

using Result = multiray::testing::CliResult;
using multiray::testing::temp_file;

Result run(const std::string& args) { return multiray::testing::run_cli(MULTIRAY_BIN, args); }

void expect_input_error(const std::string& args, const std::string& word) {
  multiray::testing::expect_input_error(run(args), args, word);
}

TEST(Cli, HelpExplainsCommandsAndOptions) {
  const Result r = run("render --help");
  EXPECT_EQ(r.code, 0);
  for (const char* opt : {"--res", "--spp", "--bounces", "--frames", "--camera-path", "--out",
                          "--exr", "--devices", "--balancer"})
    EXPECT_THAT(r.out, ::testing::HasSubstr(opt));
  EXPECT_EQ(run("--help").code, 0);
}

TEST(Cli, RendersDefaultSceneToPngAndStats) {
  const std::string dir = ::testing::TempDir() + "/cli_out";
  std::filesystem::remove_all(dir);
  const Result r = run("render --res 32x24 --spp 1 --frames 2 --exr --out " + dir);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(std::filesystem::file_size(dir + "/frame_0000.png") > 100);
  EXPECT_TRUE(std::filesystem::exists(dir + "/frame_0001.png"));
  EXPECT_TRUE(std::filesystem::exists(dir + "/frame_0001.exr"));
  EXPECT_TRUE(std::filesystem::exists(dir + "/stats.json"));
  EXPECT_THAT(r.out, ::testing::HasSubstr("frame    1"));
}

TEST(Cli, LightFieldWritesEveryViewAndAQuilt) {
  const std::string dir = ::testing::TempDir() + "/cli_views";
  std::filesystem::remove_all(dir);
  const Result r =
      run("render --res 16x8 --spp 1 --views 2x2 --devices cpu,cpu --balancer dlb "
          "--mapping views --out " +
          dir);
  ASSERT_EQ(r.code, 0) << r.out;
  for (int v = 0; v < 4; ++v)
    EXPECT_TRUE(std::filesystem::exists(dir + "/frame_0000_view0" + std::to_string(v) + ".png"));
  EXPECT_TRUE(std::filesystem::exists(dir + "/frame_0000_quilt.png"));
}

TEST(Cli, BadOptionsAndValues) {
  expect_input_error("render --no-such-option", "no-such-option");
  expect_input_error("render --res 0x10", "--res");
  expect_input_error("render --res 100000x100000", "--res");
  expect_input_error("render --res axb", "--res");
  expect_input_error("render --spp -1", "--spp");
  expect_input_error("render --spp abc", "spp");
  expect_input_error("render --camera 1,2,3", "--camera");
  expect_input_error("render --camera-path /nonexistent/path.json", "path.json");
  expect_input_error("render --devices gpu:0", "gpu");
  expect_input_error("render --devices cpu:threads=x", "threads");
  expect_input_error("render --devices cpu:speed=2", "speed");
  expect_input_error("render --devices cpu:colour=red", "colour");
  expect_input_error("render --devices cpu,cpu --perturb 5:7:0.5", "--perturb");
  expect_input_error("render --perturb 5:0", "--perturb");
  expect_input_error("render --balancer nonsense", "--balancer");
  expect_input_error("render --views 3", "--views");
  expect_input_error("render --views 0x2", "--views");
  expect_input_error("render --views 3x3 --mapping diagonal", "--mapping");
  expect_input_error("render --views 3x3 --balancer hybrid --mapping views", "--mapping");
}

TEST(Cli, FoveatedSamplingRendersAndChecksItsOptions) {
  const std::string dir = ::testing::TempDir() + "/cli_foveated";
  std::filesystem::remove_all(dir);
  const Result r =
      run("render --res 48x32 --integrator ao --sampling foveated --gaze 0.2,0.3 "
          "--gaze-path orbit:4 --frames 2 --devices cpu,cpu --balancer semi-static --out " +
          dir);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(std::filesystem::exists(dir + "/frame_0001.png"));
  std::ifstream stats(dir + "/stats.json");
  const std::string json((std::istreambuf_iterator<char>(stats)),
                         std::istreambuf_iterator<char>());
  EXPECT_THAT(json, ::testing::HasSubstr("sampling_ms"));
  expect_input_error("render --sampling foveated --gaze 2,0.5", "--gaze");
  expect_input_error("render --sampling foveated --gaze 0.5", "--gaze");
  expect_input_error("render --sampling foveated --gaze-path spiral", "--gaze-path");
  expect_input_error("render --sampling foveated --periphery-spp 0", "--periphery-spp");
  expect_input_error("render --sampling foveated --fovea-radius -1", "--fovea-radius");
  expect_input_error("render --sampling foveated --devices opencl", "opencl");
  expect_input_error("render --sampling sparse", "--sampling");
}

TEST(Cli, ReprojectedSamplingRendersEveryViewAndChecksItsOptions) {
  const std::string dir = ::testing::TempDir() + "/cli_reproject";
  std::filesystem::remove_all(dir);
  const Result r =
      run("render --res 32x24 --spp 2 --views 3x3 --view-spacing 0.3 --sampling reproject "
          "--devices cpu,cpu --balancer dlb --out " +
          dir);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(std::filesystem::exists(dir + "/frame_0000_view08.png"));
  std::ifstream stats(dir + "/stats.json");
  const nlohmann::json j = nlohmann::json::parse(stats);
  const nlohmann::json& frame = j["frames"][0];
  ASSERT_TRUE(frame.contains("reprojection")) << frame.dump();
  EXPECT_EQ(frame["reprojection"]["reference_views"], nlohmann::json::array({4}));
  const double holes = frame["reprojection"]["hole_fraction"];
  EXPECT_GT(holes, 0.0);
  EXPECT_LT(holes, 1.0);
  expect_input_error("render --sampling reproject", "several views");
  expect_input_error("render --views 3x3 --sampling reproject --spp 300", "255");
  expect_input_error("render --views 3x3 --sampling reproject --reference-spacing 65",
                     "--reference-spacing");
}

// --view-spacing auto is a thirtieth of the camera's distance to its target (3.9 for the
// built-in Cornell box); an explicit value stays in scene units; stats.json says which.
TEST(Cli, ViewSpacingIsRelativeUnlessGiven) {
  const std::string dir = ::testing::TempDir() + "/cli_view_spacing";
  const auto spacing = [&](const std::string& extra) {
    std::filesystem::remove_all(dir);
    const Result r = run("render --res 16x12 --spp 1 --views 2x2 --out " + dir + extra);
    EXPECT_EQ(r.code, 0) << r.out;
    return nlohmann::json::parse(std::ifstream(dir + "/stats.json"))["settings"]["view_spacing"]
        .get<double>();
  };
  EXPECT_NEAR(spacing(""), 3.9 / 30, 1e-5);
  EXPECT_NEAR(spacing(" --view-spacing 0.3"), 0.3, 1e-6);
  EXPECT_NEAR(spacing(" --view-spacing auto"), 3.9 / 30, 1e-5);
  expect_input_error("render --views 2x2 --view-spacing -1", "--view-spacing");
  expect_input_error("render --views 2x2 --view-spacing far", "--view-spacing");
}

TEST(Cli, UpExposureAndToneAreChecked) {
  expect_input_error("render --res 8x8 --up w", "--up");
  expect_input_error("render --res 8x8 --up yz", "--up");
  expect_input_error("render --res 8x8 --up ++y", "--up");
  expect_input_error("render --res 8x8 --up Z", "--up");
  expect_input_error("render --res 8x8 --exposure 20.5", "--exposure");
  expect_input_error("render --res 8x8 --exposure -21", "--exposure");
  expect_input_error("render --res 8x8 --exposure nan", "--exposure");
  expect_input_error("render --res 8x8 --exposure two", "--exposure");
  expect_input_error("render --res 8x8 --tone aces", "--tone");
  const Result help = run("render --help-all");
  for (const char* opt : {"--up", "--exposure", "--tone", "filmic"})
    EXPECT_THAT(help.out, ::testing::HasSubstr(opt));
}

// stats.json alone says how the run was made.
TEST(Cli, StatsJsonRecordsTheRunSettings) {
  const std::string dir = ::testing::TempDir() + "/cli_settings";
  std::filesystem::remove_all(dir);
  const Result r =
      run("render --res 40x24 --spp 3 --bounces 5 --seed 42 --devices cpu:threads=1 "
          "--balancer uniform --exposure 1.5 --tone clamp -q --out " +
          dir);
  ASSERT_EQ(r.code, 0) << r.out;
  const auto doc = nlohmann::json::parse(std::ifstream(dir + "/stats.json"));
  const auto& s = doc.at("settings");
  const auto cmd = s.at("command_line").get<std::vector<std::string>>();
  ASSERT_GE(cmd.size(), 3u);
  EXPECT_EQ(cmd[1], "render");
  EXPECT_EQ(cmd.back(), dir);
  const std::string version = run("--version").out;
  EXPECT_EQ("multiray " + s.at("version").get<std::string>() + "\n", version);
  EXPECT_EQ(s.at("resolution"), nlohmann::json({40, 24}));
  EXPECT_EQ(s.at("spp"), 3);
  EXPECT_EQ(s.at("bounces"), 5);
  EXPECT_EQ(s.at("seed"), 42);
  EXPECT_EQ(s.at("frames"), 1);
  EXPECT_EQ(s.at("devices"), "cpu:threads=1");
  EXPECT_EQ(s.at("balancer"), "uniform");
  EXPECT_EQ(s.at("integrator"), "path");
  EXPECT_EQ(s.at("exposure_ev"), 1.5);
  EXPECT_EQ(s.at("tone"), "clamp");
  EXPECT_EQ(s.at("camera").at("source"), "scene");  // the Cornell box's own
  EXPECT_EQ(s.at("camera").at("eye"), nlohmann::json({0.0, 1.0, 3.9f}));
  EXPECT_EQ(s.at("camera").at("fov_y_deg"), 39.3f);

  // A file without a camera: the default one, about --up.
  const std::string obj = temp_file("settings.obj", "v 0 0 0\nv 1 0 0\nv 0 1 2\nf 1 2 3\n");
  std::filesystem::remove_all(dir);
  ASSERT_EQ(run("render " + obj + " --res 16x8 --spp 1 --up z -q --out " + dir).code, 0);
  const auto doc2 = nlohmann::json::parse(std::ifstream(dir + "/stats.json"));
  const auto& s2 = doc2.at("settings");
  EXPECT_EQ(s2.at("camera").at("source"), "default");
  EXPECT_EQ(s2.at("up"), nlohmann::json({0.0, 0.0, 1.0}));
  EXPECT_EQ(s2.at("camera").at("up"), nlohmann::json({0.0, 0.0, 1.0}));
  EXPECT_EQ(s2.at("tone"), "filmic");    // meshes' default
  EXPECT_EQ(s2.at("exposure"), "auto");  // metered (tests/cli/output_names_cli_test.cpp)
  EXPECT_EQ(s2.at("scene"), obj);

  // A volume: viewed about z, PNGs clamped (the raycaster writes display colours).
  std::string voxels(16 * 16 * 16, '\0');
  for (size_t i = 0; i < voxels.size(); ++i) voxels[i] = char(i % 16 < 8 ? 200 : 0);
  const std::string raw = temp_file("settings.raw", voxels);
  std::filesystem::remove_all(dir);
  const Result rv = run("render " + raw + " --raw 16x16x16:uint8 --res 16x8 -q --out " + dir);
  ASSERT_EQ(rv.code, 0) << rv.out;
  const auto doc3 = nlohmann::json::parse(std::ifstream(dir + "/stats.json"));
  const auto& s3 = doc3.at("settings");
  EXPECT_EQ(s3.at("tone"), "clamp");
  EXPECT_EQ(s3.at("exposure"), "fixed");  // display colours: auto leaves them alone
  EXPECT_EQ(s3.at("exposure_ev"), 0.0);
  EXPECT_EQ(s3.at("integrator"), "volume");
  EXPECT_EQ(s3.at("up"), nlohmann::json({0.0, 0.0, 1.0}));
  EXPECT_EQ(s3.at("camera").at("source"), "default");
}

// `--camera default` frames the scene even where the file has a camera of its own (the
// built-in Cornell box has one).
TEST(Cli, CameraDefaultOverridesTheFilesCamera) {
  const std::string dir = ::testing::TempDir() + "/cli_camera_default";
  std::filesystem::remove_all(dir);
  ASSERT_EQ(run("render --res 16x8 --spp 1 -q --camera default --out " + dir).code, 0);
  const auto doc = nlohmann::json::parse(std::ifstream(dir + "/stats.json"));
  EXPECT_EQ(doc.at("settings").at("camera").at("source"), "default");
  EXPECT_NE(doc.at("settings").at("camera").at("eye"), nlohmann::json({0.0, 1.0, 3.9f}));
}

// A format that carries no up axis and usually comes from a Z-up tool gets a hint (issue 32:
// "a Z-up file lies on its side with no hint"); with --up given, it is not repeated.
TEST(Cli, ZUpFormatsWithoutAnAxisGetAHint) {
  const std::string stl = temp_file("hint.stl",
                                    "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"
                                    "vertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n");
  const std::string dir = ::testing::TempDir() + "/cli_zup_hint";
  std::filesystem::remove_all(dir);
  const Result r = run("render " + stl + " --res 8x8 --spp 1 -q --out " + dir);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_THAT(r.out, ::testing::HasSubstr("pass --up z"));
  std::filesystem::remove_all(dir);
  const Result given = run("render " + stl + " --res 8x8 --spp 1 -q --up z --out " + dir);
  EXPECT_THAT(given.out, ::testing::Not(::testing::HasSubstr("--up z")));
}

// `devices --devices ... --scene FILE` reports each device's scene memory, within
// --max-memory like render: the scene is estimated before it loads and refused in one line.
TEST(Cli, DevicesOnASceneStayWithinMaxMemory) {
  const std::string obj =
      temp_file("devices_scene.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n");
  const Result ok = run("devices --devices cpu,cpu:compact=1 --scene " + obj);
  ASSERT_EQ(ok.code, 0) << ok.out;
  EXPECT_THAT(ok.out, ::testing::HasSubstr("compact"));
  expect_input_error("devices --devices cpu --scene " + obj + " --max-memory 100", "--max-memory");
}

TEST(Cli, BadSceneFiles) {
  expect_input_error("render /nonexistent/scene.obj --res 8x8", "scene.obj");
  expect_input_error("render " + temp_file("bad.xyz", "hello") + " --res 8x8", "bad.xyz");
  expect_input_error("render " + temp_file("empty.ply", "") + " --res 8x8", "empty.ply");
  expect_input_error(
      "render " +
          temp_file("trunc.ply",
                    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                    "property float y\nproperty float z\nelement face 1\n"
                    "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n") +
          " --res 8x8",
      "trunc.ply");
  expect_input_error(
      "render " + temp_file("nan.obj", "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n") + " --res 8x8",
      "nan.obj");
  expect_input_error(
      "render " + temp_file("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n") + " --res 8x8",
      "range.obj");
  expect_input_error(
      "render " + temp_file("flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n") + " --res 8x8",
      "flat.obj");
  expect_input_error(
      "render " + temp_file("broken.gltf", "{\"asset\": {\"version\": \"2.0\"") + " --res 8x8",
      "broken.gltf");
}

}  // namespace cli_test

namespace cli_test {

// --trace writes every item once: per frame, the items' areas add up to the image.
TEST(Cli, TraceRecordsEveryItemOfEveryFrame) {
  const std::string dir = ::testing::TempDir() + "/cli_trace";
  std::filesystem::remove_all(dir);
  const std::string trace = dir + ".trace";
  const Result r =
      run("render --res 40x24 --spp 1 --frames 3 --camera-path orbit:6 --devices "
          "cpu,cpu:speed=0.5 --balancer hybrid -q --trace " +
          trace + " --out " + dir);
  ASSERT_EQ(r.code, 0) << r.out;
  std::ifstream in(trace);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "multiray-trace 1");
  std::vector<long> area;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string kind;
    ls >> kind;
    if (kind == "frame") area.push_back(0);
    if (kind != "item") continue;
    long device, id, view, x0, y0, x1, y1;
    ls >> device >> id >> view >> x0 >> y0 >> x1 >> y1;
    area.back() += (x1 - x0) * (y1 - y0);
  }
  EXPECT_EQ(area, (std::vector<long>{40 * 24, 40 * 24, 40 * 24}));
  expect_input_error("render --res 8x8 --trace /nonexistent/dir/t.trace --out " + dir, "trace");
}

TEST(Cli, DepthKernelRunsAndUnknownKernelsAreRefused) {
  const std::string dir = ::testing::TempDir() + "/cli_depth";
  std::filesystem::remove_all(dir);
  const Result r = run("render --res 16x12 --integrator depth --devices cpu,cpu --out " + dir);
  EXPECT_EQ(r.code, 0) << r.out;
  expect_input_error("render --integrator nothing", "--integrator");
}

}  // namespace cli_test

namespace cli_test {

// A trace recorded by render, replayed by simulate on more devices behind a link.
TEST(Cli, SimulateReplaysARecordedTrace) {
  const std::string dir = ::testing::TempDir() + "/cli_sim";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string trace = dir + "/run.trace";
  ASSERT_EQ(run("render -q --res 32x24 --spp 1 --frames 3 --devices cpu,cpu --trace " + trace +
                " --out " + dir)
                .code,
            0);
  const Result r = run("simulate " + trace +
                       " --devices 2,8 --link wifi --slowdown 20 --frames 6 "
                       "--balancers uniform,hybrid --json " +
                       dir + "/sim.json --plot " + dir + "/sim.svg");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_THAT(r.out, ::testing::HasSubstr("virtual time"));
  EXPECT_THAT(r.out, ::testing::HasSubstr("hybrid"));
  EXPECT_GT(std::filesystem::file_size(dir + "/sim.svg"), 500u);
  std::ifstream json(dir + "/sim.json");
  const std::string text((std::istreambuf_iterator<char>(json)), {});
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n') > 10, true);
  expect_input_error("simulate " + trace + " --devices 0", "--devices");
  expect_input_error("simulate " + trace + " --link moon", "--link");
  expect_input_error("simulate " + trace + " --speeds linear:7", "--speeds");
  expect_input_error("simulate " + trace + " --balancers nonsense", "--balancers");
  expect_input_error("simulate /nonexistent.trace", "trace");
  expect_input_error("simulate " + temp_file("bad.trace", "multiray-trace 1\nframe 0 -4 4 1\n"),
                     "line 2");
}

}  // namespace cli_test

namespace cli_test {

// simulate --calibrate / --predict: the calibration and the comparison table on traces
// recorded by render; a real trace of another frame size is refused in one line.
TEST(Cli, SimulatePredictsFromACalibratedTrace) {
  const std::string dir = ::testing::TempDir() + "/cli_simcal";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  auto record = [&](const std::string& balancer, const std::string& res) {
    const std::string trace = dir + "/" + balancer + "-" + res + ".trace";
    EXPECT_EQ(
        run("render -q --res " + res + " --spp 1 --frames 4 --devices cpu,cpu --balancer " +
            balancer + " --trace " + trace + " --out " + dir + "/out-" + balancer + "-" + res)
            .code,
        0);
    return trace;
  };
  const std::string cal = record("hybrid", "32x24"), queue = record("queue", "32x24"),
                    uniform = record("uniform", "32x24"), small = record("queue", "16x12");
  const Result r = run("simulate " + cal + " --predict " + queue + "," + uniform +
                       " --warmup 1 --json " + dir + "/predict.json");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_THAT(r.out, ::testing::HasSubstr("item cost ms"));
  EXPECT_THAT(r.out, ::testing::HasSubstr("contention"));
  EXPECT_THAT(r.out, ::testing::HasSubstr("\nqueue"));
  EXPECT_THAT(r.out, ::testing::HasSubstr("\nuniform"));
  std::ifstream json(dir + "/predict.json");
  const std::string text((std::istreambuf_iterator<char>(json)), {});
  for (const char* key :
       {"\"calibration\"", "\"real_mean_ms\"", "\"simulated_mean_ms\"", "\"mean_abs_error\"",
        "\"bias\"", "\"item_overhead_ms\"", "\"frame_overhead_ms\"", "\"contention\""})
    EXPECT_THAT(text, ::testing::HasSubstr(key));
  const Result c = run("simulate " + cal + " --calibrate --contention 0.1 --balancers uniform");
  ASSERT_EQ(c.code, 0) << c.out;
  EXPECT_THAT(c.out, ::testing::HasSubstr("given by --contention"));
  expect_input_error("simulate " + cal + " --predict " + small, "16x12");
  expect_input_error("simulate " + cal + " --predict " + queue + ",/nonexistent.trace",
                     "nonexistent");
  expect_input_error("simulate " + cal + " --calibrate --contention -2", "--contention");
}

}  // namespace cli_test
