// `--distributed` under mpirun, run as a user would: a frame rendered by a master and
// workers is bit-identical to the same frame rendered by one process, for every balancer
// at the master, Seo's two strategies, Harada's two-level split, links, multiview and
// adaptive sampling; a worker killed mid-run costs no pixel; bad setups fail in one line.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "support/run_cli.h"

namespace distributed_test {

using multiray::testing::CliResult;

// As root, Open MPI needs both switches; two cores hold four ranks only oversubscribed.
const std::string kMpirun = std::string(MULTIRAY_MPIEXEC) + " --oversubscribe --allow-run-as-root";

CliResult single(const std::string& args) {
  return multiray::testing::run_cli(MULTIRAY_BIN, args);
}
CliResult distributed(int ranks, const std::string& args, const std::string& mpi_flags = "",
                      const std::string& env = "", int timeout_s = 120) {
  return multiray::testing::run_cli(
      kMpirun + " -np " + std::to_string(ranks) + " " + mpi_flags + " " + MULTIRAY_BIN,
      args + " --distributed", env, timeout_s);
}

std::string out_dir(const std::string& name) {
  // Named per test: ctest runs the tests of this file in parallel processes.
  const std::string dir = ::testing::TempDir() + "/mpi_" +
                          ::testing::UnitTest::GetInstance()->current_test_info()->name() + "_" +
                          name;
  std::filesystem::remove_all(dir);
  return dir;
}

nlohmann::json stats(const std::string& dir) {
  std::ifstream in(dir + "/stats.json");
  return nlohmann::json::parse(in);
}

// One hash per frame. A missing or empty stats.json fails here, so two empty lists can
// never compare equal. (The json is held in a local: a range-for over a member of a
// temporary returned through operator[] would read a destroyed object.)
std::vector<std::string> hashes(const std::string& dir) {
  const nlohmann::json s = stats(dir);
  std::vector<std::string> h;
  for (const auto& f : s.at("frames")) h.push_back(f.at("image_hash").get<std::string>());
  EXPECT_FALSE(h.empty()) << dir << "/stats.json has no frames";
  return h;
}

// Two frames of an orbit, so the balancers' second plans (from measurements) count too.
const std::string kScene =
    "render --res 80x48 --spp 2 --bounces 3 --frames 2 "
    "--camera-path orbit:10 -q ";

std::vector<std::string> reference(const std::string& extra) {
  const std::string dir = out_dir("reference");
  const CliResult r = single(kScene + extra + " --devices cpu:threads=1 --out " + dir);
  EXPECT_EQ(r.code, 0) << r.out;
  return hashes(dir);
}

TEST(Distributed, EveryBalancerAtTheMasterGivesTheSinglePixels) {
  const std::vector<std::string> want = reference("");
  for (const char* balancer :
       {"uniform", "static", "queue:tile=16", "semi-static", "dlb", "hybrid", "bruder", "cycles",
        "equalizer", "ospray-static:tile=16", "ospray-dynamic:tile=16"}) {
    const std::string dir = out_dir("balancer");
    const CliResult r = distributed(
        3, kScene + "--devices cpu:threads=1 --balancer " + balancer + " --out " + dir);
    ASSERT_EQ(r.code, 0) << balancer << ": " << r.out;
    EXPECT_EQ(hashes(dir), want) << balancer;
    EXPECT_THAT(stats(dir)["devices"][0]["name"].get<std::string>(),
                ::testing::HasSubstr("rank 1"));
  }
}

// Seo et al.'s strategies on four ranks (three workers), over the emulated mobile link, and
// Harada's hierarchy: bands across ranks, each band split across a rank's own devices in
// the other direction by every balancer at the lower level.
TEST(Distributed, FourRanksSeoStrategiesAndHaradaHierarchyGiveTheSinglePixels) {
  const std::vector<std::string> want = reference("");
  const std::string two_devices = " --rank-devices 1=cpu:threads=1,cpu:threads=1:speed=0.5";
  const std::vector<std::string> runs = {
      "--balancer queue:tile=16 --link wifi",  // Seo I: dynamic tile queue
      "--balancer queue:tile=16:pipeline=deep --depth auto --link wifi",  // Seo I, ours
      "--balancer ospray-static:tile=16 --link wifi",                     // Seo II: static batched
      "--balancer hybrid --master-renders --link lan",                    // master renders too
      "--balancer semi-static --rank-balancer semi-static" + two_devices,  // Harada
      "--balancer semi-static --rank-balancer hybrid --rank-same-direction" + two_devices,
      "--balancer uniform --rank-balancer queue:tile=8" + two_devices,
  };
  for (const std::string& run : runs) {
    const std::string dir = out_dir("four");
    const CliResult r =
        distributed(4, kScene + "--devices cpu:threads=1 " + run + " --out " + dir);
    ASSERT_EQ(r.code, 0) << run << ": " << r.out;
    EXPECT_EQ(hashes(dir), want) << run;
    // The master is the top of Harada's hierarchy: its semi-static cuts row bands
    // (balance/hierarchy.h; the ranks' directions are checked in hierarchy_test.cpp).
    if (run.rfind("--balancer semi-static ", 0) == 0) {
      EXPECT_THAT(stats(dir)["balancer"].get<std::string>(), ::testing::HasSubstr("split=rows"))
          << run;
    }
  }
}

// --balancer auto (the default) is resolved on the master, which sees each worker as a
// remote device behind the link: recorded with the ranks and the link in its reason.
TEST(Distributed, AutoIsResolvedOnTheMasterFromTheWorkersAndTheLink) {
  const std::string dir = out_dir("auto");
  const CliResult r = distributed(
      3, "render --res 40x24 --spp 1 --frames 1 --devices cpu:threads=1 --link wifi --out " + dir);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_THAT(r.out, ::testing::HasSubstr("multiray: --balancer auto: hybrid (2 devices (remote"));
  const nlohmann::json s = stats(dir);
  EXPECT_EQ(s.at("settings").at("balancer"), "auto");
  EXPECT_EQ(s.at("balancer_auto").at("spec"), "hybrid");
  EXPECT_THAT(s.at("balancer_auto").at("reason").get<std::string>(),
              ::testing::HasSubstr("3 ranks, link 5 ms, 200 Mbit/s; over a link"));
  EXPECT_THAT(s.at("balancer").get<std::string>(), ::testing::StartsWith("hybrid:"));
}

TEST(Distributed, MultiviewAdaptiveAndReprojectedSamplingGiveTheSinglePixels) {
  const std::string extra = "--views 2x1 --sampling adaptive ";
  const std::vector<std::string> want = reference(extra);
  const std::string dir = out_dir("views");
  const CliResult r = distributed(
      3, kScene + extra + "--devices cpu:threads=1 --balancer dlb --mapping strips --out " + dir);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_EQ(hashes(dir), want);
  // Reprojection: the holes' sample maps travel to the workers, the master fills the rest.
  const std::string reproject = "--views 3x1 --sampling reproject ";
  const std::vector<std::string> want_reprojected = reference(reproject);
  const std::string dir2 = out_dir("reprojected");
  const CliResult r2 = distributed(
      3, kScene + reproject + "--devices cpu:threads=1 --balancer semi-static --out " + dir2);
  ASSERT_EQ(r2.code, 0) << r2.out;
  EXPECT_EQ(hashes(dir2), want_reprojected);
  EXPECT_NE(want_reprojected, reference("--views 3x1 "));  // it did reproject
}

// A worker that vanishes (SIGKILL at frame 1) is given up on after --worker-timeout; what
// it owed is re-rendered by the others and every frame is still complete and exact. Open
// MPI keeps the other ranks alive only with --enable-recovery.
TEST(Distributed, AKilledWorkerCostsNoPixel) {
  const std::string frames =
      "render --res 80x48 --spp 2 --bounces 3 --frames 3 "
      "--camera-path orbit:10 ";
  const std::string ref = out_dir("killed_ref");
  ASSERT_EQ(single(frames + "-q --devices cpu:threads=1 --out " + ref).code, 0);
  for (const char* balancer : {"queue:tile=16", "semi-static"}) {
    const std::string dir = out_dir("killed");
    const CliResult r =
        distributed(3,
                    frames + "--devices cpu:threads=1 --worker-timeout 1 --balancer " + balancer +
                        " --out " + dir,
                    "--enable-recovery -x MULTIRAY_TEST_KILL", "MULTIRAY_TEST_KILL=2:1",
                    // The run takes ~3 s. Every rank must end: a surviving worker that
                    // called MPI_Finalize waited there for the dead rank forever (the
                    // master's Quit now tells it not to), and timeout's 124 fails below.
                    30);
    EXPECT_EQ(r.code, 0) << balancer << ": " << r.out;
    ASSERT_TRUE(std::filesystem::exists(dir + "/stats.json")) << balancer << ": " << r.out;
    EXPECT_THAT(r.out, ::testing::HasSubstr("rank 2: no answer"));
    EXPECT_EQ(hashes(dir), hashes(ref)) << balancer;
    EXPECT_EQ(stats(dir)["frames"].size(), 3u);
  }
}

// The master killed mid-run (kill -9, a crashed machine): with --enable-recovery mpirun
// keeps the other ranks, which used to wait for it forever. Each worker now notices the
// master's heartbeats stop and ends within --worker-timeout, non-zero, saying why.
TEST(Distributed, AKilledMasterEndsEveryWorker) {
  const auto start = std::chrono::steady_clock::now();
  const CliResult r =
      distributed(3,
                  "render -q --res 80x48 --spp 2 --frames 1000 "
                  "--camera-path orbit:10 --devices cpu:threads=1 "
                  "--worker-timeout 2 --out " +
                      out_dir("master_killed"),
                  "--enable-recovery -x MULTIRAY_TEST_KILL", "MULTIRAY_TEST_KILL=0:2", 60);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // timeout's code (mpirun's own code with --enable-recovery is its policy, not ours).
  EXPECT_NE(r.code, 124) << "the workers outlived the master: " << r.out;
  EXPECT_THAT(r.out, ::testing::HasSubstr("rank 1: nothing from the master"));
  EXPECT_THAT(r.out, ::testing::HasSubstr("rank 2: nothing from the master"));
  EXPECT_LT(seconds, 45) << r.out;
}

// A master that sends no work for longer than --worker-timeout is alive all the same: its
// heartbeats say so. Here the emulated link holds every message 1.5 s, longer than the
// 1 s timeout; without the master's heartbeats the workers took it for dead and ended.
TEST(Distributed, AQuietMasterIsNotTakenForDead) {
  const std::string dir = out_dir("quiet");
  const CliResult r = distributed(3,
                                  "render -q --res 32x18 --spp 1 --frames 2 "
                                  "--devices cpu:threads=1 --worker-timeout 1 "
                                  "--link 1500,1000 --out " +
                                      dir);
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_THAT(r.out, ::testing::Not(::testing::HasSubstr("nothing from the master")));
  EXPECT_EQ(stats(dir)["frames"].size(), 2u);
}

TEST(Distributed, BadSetupsFailInOneLine) {
  const std::string dir = out_dir("bad");
  // One rank is no cluster.
  CliResult r = distributed(1, "render --res 16x16 --spp 1 --out " + dir);
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_THAT(r.out, ::testing::HasSubstr("at least one worker"));
  // A worker that cannot create its devices: the master names it, nobody hangs.
  r = distributed(2, "render --res 16x16 --spp 1 --rank-devices 1=gpu --out " + dir);
  EXPECT_NE(r.code, 0) << r.out;
  EXPECT_THAT(r.out, ::testing::HasSubstr("rank 1: --devices 'gpu'"));
  r = distributed(2, "render --res 16x16 --spp 1 --link fast --out " + dir);
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_THAT(r.out, ::testing::HasSubstr("--link 'fast'"));
  r = distributed(2, "render --res 16x16 --spp 1 --sampling foveated --out " + dir);
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_THAT(r.out, ::testing::HasSubstr("foveated"));
}

// A worker's result longer than one part of the transport (128 KiB: half of a 320x180
// frame with its feature buffers as floats is 1.6 MB: 56 bytes a pixel) crosses in parts and is
// joined whole: the frame and its feature buffers are one process's to the bit.
TEST(Distributed, AResultLongerThanAPartArrivesWhole) {
  const std::string args =
      "render --res 320x180 --spp 1 --frames 1 -q --balancer uniform "
      "--result-encoding float --devices cpu:threads=1 --out ";
  const std::string one = out_dir("one"), three = out_dir("three");
  const CliResult a = single(args + one);
  ASSERT_EQ(a.code, 0) << a.out;
  const CliResult b = distributed(3, args + three);
  ASSERT_EQ(b.code, 0) << b.out;
  EXPECT_EQ(hashes(three), hashes(one));
  const std::string feature = stats(one)["frames"][0]["feature_hash"].get<std::string>();
  EXPECT_EQ(stats(three)["frames"][0]["feature_hash"].get<std::string>(), feature);
  EXPECT_GT(stats(three)["frames"][0]["result_bytes"][0].get<double>(), 2.0 * 131072);
}

// --result-encoding: compressed floats give the master the very pixels of plain floats
// (and of one process) in fewer bytes; halves give one image whatever the split (each
// pixel is rounded on its own), unlike the floats' image. Two workers, one 64x64 frame.
TEST(Distributed, ResultEncodingsOverTheWire) {
  const std::string args = "render -q --res 64x64 --spp 1 --bounces 2 --devices cpu:threads=1 ";
  const std::string ref = out_dir("ref");
  ASSERT_EQ(single(args + "--out " + ref).code, 0);
  const auto run = [&](const std::string& extra) {
    const std::string dir = out_dir("run");
    const CliResult r = distributed(3, args + extra + " --out " + dir);
    EXPECT_EQ(r.code, 0) << extra << ": " << r.out;
    const nlohmann::json s = stats(dir);
    uint64_t bytes = 0;
    for (const auto& b : s.at("frames").at(0).at("result_bytes")) bytes += b.get<uint64_t>();
    return std::pair{hashes(dir), bytes};
  };
  const auto [plain, plain_bytes] = run("--result-encoding float --balancer uniform");
  const auto [packed, packed_bytes] = run("--result-encoding float+zstd --balancer uniform");
  EXPECT_EQ(plain, hashes(ref));
  EXPECT_EQ(packed, plain);
  EXPECT_GT(plain_bytes, 64u * 64 * 12);  // every pixel, 12 bytes each, and the headers
  EXPECT_LT(packed_bytes, plain_bytes);
  const auto [half_rows, half_bytes] = run("--result-encoding half --balancer uniform");
  const std::vector<std::string> half_tiles =
      run("--result-encoding half --balancer queue:tile=16").first;
  EXPECT_EQ(half_rows, half_tiles);
  EXPECT_NE(half_rows, plain);
  EXPECT_LT(half_bytes, plain_bytes);
  const CliResult mixed = distributed(2, args + "--result-encoding half --master-renders");
  EXPECT_EQ(mixed.code, 2) << mixed.out;
  EXPECT_THAT(mixed.out, ::testing::HasSubstr("--master-renders"));
}

// --aov: the feature buffers come back from the workers with the pixels, in the frame's
// result encoding, and are the single process's to the bit (stats.json's feature_hash),
// whether they travel as floats or zstd-packed, in rows or tiles, from three ranks or
// four with Harada's hierarchy (each worker splitting its band over two devices).
TEST(Distributed, FeatureBuffersArriveFromWorkersAsASingleProcessMakesThem) {
  const std::string args =
      "render -q --res 48x32 --spp 2 --bounces 2 --devices cpu:threads=1 --aov albedo,depth ";
  const auto feature_hash = [](const std::string& dir) {
    const nlohmann::json s = stats(dir);
    return s.at("frames").at(0).at("feature_hash").get<std::string>();
  };
  const std::string ref = out_dir("ref");
  ASSERT_EQ(single(args + "--out " + ref).code, 0);
  for (const auto& [ranks, extra] : std::vector<std::pair<int, std::string>>{
           {3, "--balancer uniform --result-encoding float"},
           {3, "--balancer queue:tile=16 --result-encoding float+zstd"},
           {4,
            "--balancer semi-static --rank-balancer hybrid --rank-devices "
            "1=cpu:threads=1,cpu:threads=1:speed=0.5"}}) {
    const std::string dir = out_dir("run");
    const CliResult r = distributed(ranks, args + extra + " --out " + dir);
    ASSERT_EQ(r.code, 0) << extra << ": " << r.out;
    EXPECT_EQ(feature_hash(dir), feature_hash(ref)) << extra;
    EXPECT_EQ(hashes(dir), hashes(ref)) << extra;
    EXPECT_TRUE(std::filesystem::exists(dir + "/frame_0000_aov.exr")) << extra;
  }
}

// --scene-from master: the workers are given a scene path that does not exist (mpirun's
// MPMD form gives ranks different command lines) and still render the master's scene
// bit for bit; without it, the worker that cannot load says so through the master.
TEST(Distributed, TheMasterSendsTheScene) {
  // A glTF whose texture is a separate file: the texels must travel too.
  const std::string scene =
      std::string(MULTIRAY_ASSIMP_MODELS_DIR) + "/glTF2/BoxTextured-glTF/BoxTextured.gltf";
  if (!std::filesystem::exists(scene)) GTEST_SKIP() << scene << " missing (assimp-testmodels)";
  const std::string args = " --res 64x48 --spp 2 --bounces 3 -q --devices cpu:threads=1 ";
  const std::string ref = out_dir("ref");
  ASSERT_EQ(single("render " + scene + args + "--out " + ref).code, 0);
  const auto mpmd = [&](const std::string& extra, const std::string& dir) {
    return multiray::testing::run_cli(kMpirun + " -np 1 " + MULTIRAY_BIN,
                                      "render " + scene + args + extra + " --distributed --out " +
                                          dir + " : -np 2 " + MULTIRAY_BIN +
                                          " render /nonexistent/scene.gltf" + args + extra +
                                          " --distributed --out " + dir);
  };
  const std::string dir = out_dir("sent");
  const CliResult sent = mpmd("--scene-from master", dir);
  ASSERT_EQ(sent.code, 0) << sent.out;
  EXPECT_EQ(hashes(dir), hashes(ref));
  const CliResult shared = mpmd("", out_dir("shared"));
  EXPECT_EQ(shared.code, 2) << shared.out;
  // Both workers fail; the master names whichever told it first.
  EXPECT_THAT(shared.out, ::testing::ContainsRegex("rank [12]: /nonexistent/scene.gltf"));
}

// A worker whose copy of a file that decides pixels differs by one byte (the scene's
// material library, an environment map) is refused by the master in one line naming the
// rank and the file, and every rank ends (issue 53); identical copies in other folders
// render. mpirun's MPMD form gives the worker its own paths.
TEST(Distributed, AWorkerWithAnotherSceneOrEnvIsRefused) {
  namespace fs = std::filesystem;
  const std::string root = out_dir("copies");
  const std::string example = std::string(MULTIRAY_SOURCE_DIR) + "/examples/ar/";
  // A 4x2 Radiance map (flat RGBE pixels: rows under 8 pixels are never run-length coded).
  std::string hdr = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 4\n";
  for (int i = 0; i < 8; ++i) hdr += std::string("\x80\x80\x80\x81", 4);
  for (const char* side : {"master", "same", "other"}) {
    const std::string d = root + "/" + side;
    fs::create_directories(d);
    fs::copy_file(example + "objects.obj", d + "/objects.obj");
    fs::copy_file(example + "ar.mtl", d + "/ar.mtl");
    std::ofstream(d + "/sky.hdr", std::ios::binary) << hdr;
  }
  std::string mtl;
  {
    std::ifstream in(root + "/other/ar.mtl");
    mtl.assign(std::istreambuf_iterator<char>(in), {});
  }
  mtl[mtl.find("0.7 0.15")] = '9';  // red's Kd 0.7 becomes 0.9: one byte
  std::ofstream(root + "/other/ar.mtl", std::ios::trunc) << mtl;
  std::string other_hdr = hdr;
  other_hdr.back() = '\x82';  // one pixel brighter
  fs::create_directories(root + "/env");
  std::ofstream(root + "/env/sky.hdr", std::ios::binary) << other_hdr;

  const std::string args = " --res 32x24 --spp 1 --bounces 2 -q --devices cpu:threads=1 ";
  const auto mpmd = [&](const std::string& master, const std::string& worker) {
    const std::string dir = out_dir("run");
    return multiray::testing::run_cli(kMpirun + " -np 1 " + MULTIRAY_BIN,
                                      "render " + master + args + "--distributed --out " + dir +
                                          " : -np 1 " + MULTIRAY_BIN + " render " + worker + args +
                                          "--distributed --out " + dir);
  };
  const std::string scene = "/objects.obj --env ";
  const CliResult same = mpmd(root + "/master" + scene + root + "/master/sky.hdr",
                              root + "/same" + scene + root + "/same/sky.hdr");
  EXPECT_EQ(same.code, 0) << same.out;
  const CliResult mtl_run = mpmd(root + "/master" + scene + root + "/master/sky.hdr",
                                 root + "/other" + scene + root + "/master/sky.hdr");
  EXPECT_EQ(mtl_run.code, 2) << mtl_run.out;
  EXPECT_THAT(mtl_run.out, ::testing::HasSubstr("multiray: error: rank 1 has another scene: "
                                                "'ar.mtl' differs (content hash "));
  const CliResult env_run = mpmd(root + "/master" + scene + root + "/master/sky.hdr",
                                 root + "/same" + scene + root + "/env/sky.hdr");
  EXPECT_EQ(env_run.code, 2) << env_run.out;
  EXPECT_THAT(env_run.out, ::testing::HasSubstr("rank 1 has another scene: 'sky.hdr' differs"));
  for (const CliResult* r : {&mtl_run, &env_run}) {  // one line, from the master alone
    size_t lines = 0;
    for (size_t at = 0; (at = r->out.find("multiray: error:", at)) != std::string::npos; ++at)
      ++lines;
    EXPECT_EQ(lines, 1u) << r->out;
  }
}

}  // namespace distributed_test
