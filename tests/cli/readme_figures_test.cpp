// The figures that README.md and docs/usage.md say a command gives, checked by running that
// command as the text writes it (issue 51 item 3: the Mitsuba box's "mean display value
// 52.0" came from a test's settings, not from the command beside it). The sibling of
// readme_examples_test.cpp, which runs every command of the README's "Using it" block and
// checks exit codes and files; this one reads each claim (command and figure) out of the
// text with a pattern, so a changed figure or command is what gets checked, and a claim
// whose wording no longer matches fails as "not found" instead of passing unchecked.
//
// Checked here: deterministic figures only (image statistics, settings a command records,
// counts of files and lines). Frame times, speeds and shares of a timed split are not: they
// differ from run to run and machine to machine (docs/testing.md lists what is left and
// why). Commands run in a fresh folder of their own laid out like a clone after `make run`
// (build/, examples/, scripts/, tests/ and ../shared), so parallel runs do not collide.
#include <gtest/gtest.h>
#include <stb_image.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "support/run_cli.h"

namespace readme_figures_test {

namespace fs = std::filesystem;
using multiray::testing::run_cli;

// `path`'s text with every run of white space (line breaks and indents too) made one space
// and a shell line's continuation (a backslash before its line break) joined, so a claim or
// a command wrapped over lines reads as one.
std::string flat_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string joined = std::regex_replace(ss.str(), std::regex("\\\\\n"), " ");
  return std::regex_replace(joined, std::regex("\\s+"), " ");
}

std::string source(const std::string& relative) {
  return std::string(MULTIRAY_SOURCE_DIR) + "/" + relative;
}

// The first match of `pattern` in `text`; a failure naming `what` when there is none.
std::smatch claim(const std::string& text, const std::string& pattern, const std::string& what) {
  std::smatch m;
  const bool found = std::regex_search(text, m, std::regex(pattern));
  EXPECT_TRUE(found) << what << " not found (pattern: " << pattern << ")";
  return m;
}

bool shared_data_here() { return fs::exists(MULTIRAY_SHARED_DATA_DIR); }

// A folder like a fresh clone after `make run` (build/, examples/, scripts/, tests/ as
// links, ../shared beside it), made new for each test in a folder of its own.
class Clone {
 public:
  Clone() {
    std::string pattern = (fs::temp_directory_path() / "readme_figures.XXXXXX").string();
    root_ = mkdtemp(pattern.data()) ? pattern : "";
    dir_ = root_ + "/multiray";
    fs::create_directories(dir_);
    fs::create_directory_symlink(MULTIRAY_BUILD_DIR, dir_ + "/build");
    for (const char* d : {"examples", "scripts", "tests"})
      fs::create_directory_symlink(source(d), dir_ + "/" + d);
    const fs::path data(MULTIRAY_SHARED_DATA_DIR);
    if (fs::exists(data))
      fs::create_directory_symlink(fs::absolute(data).parent_path(), root_ + "/shared");
  }
  ~Clone() {
    std::error_code ec;
    fs::remove_all(root_, ec);
  }
  // `command` as written, run from the clone with the README's PATH export before it.
  multiray::testing::CliResult run(const std::string& command, int timeout_s = 600) const {
    const std::string script = root_ + "/claim.sh";
    std::ofstream(script) << "export PATH=\"$PWD/build/src/app:$PATH\"\n" << command << "\n";
    const auto r = run_cli("sh", script, "cd '" + dir_ + "' &&", timeout_s);
    std::printf("%s\n  exit %d\n", command.c_str(), r.code);
    return r;
  }
  std::string path(const std::string& relative) const { return dir_ + "/" + relative; }

 private:
  std::string root_, dir_;
};

// An 8-bit RGB image (PNG or JPEG) as read by stb, with its mean display value (0..255,
// over every pixel and channel) and its luminance in kBlocks x kBlocks blocks.
struct Picture {
  int w = 0, h = 0;
  std::vector<unsigned char> rgb;
  double mean() const {
    double s = 0;
    for (unsigned char v : rgb) s += v;
    return rgb.empty() ? NAN : s / double(rgb.size());
  }
  static constexpr int kBlocks = 10;
  std::vector<double> block_luminance() const {
    std::vector<double> b(kBlocks * kBlocks, 0.0);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const unsigned char* p = &rgb[3 * (size_t(y) * size_t(w) + size_t(x))];
        b[size_t(y * kBlocks / h * kBlocks + x * kBlocks / w)] +=
            0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
      }
    return b;
  }
};

Picture load_picture(const std::string& path) {
  Picture p;
  int n = 0;
  unsigned char* px = stbi_load(path.c_str(), &p.w, &p.h, &n, 3);
  EXPECT_NE(px, nullptr) << path << ": " << stbi_failure_reason();
  if (px) p.rgb.assign(px, px + size_t(p.w) * size_t(p.h) * 3), stbi_image_free(px);
  return p;
}

double correlation(const std::vector<double>& a, const std::vector<double>& b) {
  double ma = 0, mb = 0;
  for (size_t i = 0; i < a.size(); ++i) ma += a[i], mb += b[i];
  ma /= double(a.size()), mb /= double(b.size());
  double sab = 0, saa = 0, sbb = 0;
  for (size_t i = 0; i < a.size(); ++i)
    sab += (a[i] - ma) * (b[i] - mb), saa += (a[i] - ma) * (a[i] - ma),
        sbb += (b[i] - mb) * (b[i] - mb);
  return sab / std::sqrt(saa * sbb);
}

// A figure stated with `decimals` decimals holds when the measured value rounds to it
// (half a unit of its last place either way).
void expect_stated(double measured, const std::string& stated, const std::string& what) {
  const size_t dot = stated.find('.');
  const int decimals = dot == std::string::npos ? 0 : int(stated.size() - dot - 1);
  const double half_unit = 0.5 * std::pow(10.0, -decimals) + 1e-9;
  EXPECT_NEAR(measured, std::stod(stated), half_unit)
      << what << ": the text says " << stated << ", the command gives " << measured;
}

// docs/usage.md: Mitsuba's Cornell box, "`multiray render ...` gives [this](IMAGE)
// (reference: `JPEG` there), mean display value M of 255 against Mitsuba's R (P%),
// 10x10-block luminance correlation C".
TEST(ReadmeFigures, MitsubaBoxAsTheUsageDocStatesIt) {
  const std::string text = flat_text(source("docs/usage.md"));
  const std::smatch m =
      claim(text,
            "`(multiray render [^`]*variants_cbox_rgb\\.xml[^`]*)` gives \\[this\\]\\(([^)]+)\\) "
            "\\(reference: `([^`]+)` there\\), mean display value ([0-9.]+) of 255 against "
            "Mitsuba's ([0-9.]+) \\((-?[0-9]+)%\\), 10x10-block luminance correlation ([0-9.]+)",
            "docs/usage.md's Mitsuba claim");
  if (m.empty()) return;
  const std::string command = m[1], shown = m[2], reference_name = m[3];
  if (!shared_data_here()) GTEST_SKIP() << "../shared/data is absent";
  const Clone clone;
  const auto r = clone.run(command);
  ASSERT_EQ(r.code, 0) << r.out;
  // The command names its output: -o FILE.
  std::smatch out;
  ASSERT_TRUE(std::regex_search(command, out, std::regex("-o (\\S+\\.png)"))) << command;
  const Picture ours = load_picture(clone.path(out[1]));
  ASSERT_FALSE(ours.rgb.empty());
  // The reference JPEG, in the scene's repository (../shared/data/cornell_box/mitsuba).
  const std::string jpeg =
      std::string(MULTIRAY_SHARED_DATA_DIR) + "/cornell_box/mitsuba/" + reference_name;
  const Picture reference = load_picture(jpeg);
  ASSERT_FALSE(reference.rgb.empty()) << jpeg;

  expect_stated(ours.mean(), m[4], "mean display value");
  expect_stated(reference.mean(), m[5], "Mitsuba's mean display value");
  expect_stated(100 * (ours.mean() / reference.mean() - 1), m[6], "difference, %");
  expect_stated(correlation(ours.block_luminance(), reference.block_luminance()), m[7],
                "10x10-block luminance correlation");
  // The picture it links is what this command writes (same size, same mean to 0.5).
  const Picture linked = load_picture(source("docs/" + shown));
  EXPECT_EQ(linked.w, ours.w);
  EXPECT_EQ(linked.h, ours.h);
  EXPECT_NEAR(linked.mean(), ours.mean(), 0.5) << shown << " is not this command's image";
}

// docs/usage.md: an enclosed scene such as Sponza gets a camera inside, "with a N° fov
// (`stats.json`: camera source `SOURCE`)", as the README's Sponza command writes it.
TEST(ReadmeFigures, SponzasDefaultCameraAsTheUsageDocStatesIt) {
  const std::string usage = flat_text(source("docs/usage.md"));
  const std::smatch m =
      claim(usage, "with a ([0-9]+)° fov \\(`stats\\.json`: camera source `([a-z-]+)`\\)",
            "docs/usage.md's interior camera claim");
  const std::string readme = flat_text(source("README.md"));
  const std::smatch c = claim(readme,
                              "(multiray render \\S*dabrovic_sponza/sponza\\.obj -o "
                              "(\\S+)\\.png) # inside, metered",
                              "the README's Sponza command");
  if (m.empty() || c.empty()) return;
  if (!shared_data_here()) GTEST_SKIP() << "../shared/data is absent";
  const Clone clone;
  const auto r = clone.run(c[1]);
  ASSERT_EQ(r.code, 0) << r.out;
  std::ifstream in(clone.path(c[2].str() + ".stats.json"));
  ASSERT_TRUE(in) << "no " << c[2] << ".stats.json";
  const nlohmann::json stats = nlohmann::json::parse(in);
  const nlohmann::json& camera = stats.at("settings").at("camera");
  EXPECT_EQ(camera.at("source").get<std::string>(), m[2].str());
  expect_stated(camera.at("fov_y_deg").get<double>(), m[1], "the interior camera's fov");
  // "Metered": the exposure was chosen on the frame (--exposure auto).
  EXPECT_EQ(stats.at("settings").at("exposure").get<std::string>(), "auto");
}

// README.md: the cranium's interaction sequence, "# N frames ...": the frames it writes.
TEST(ReadmeFigures, CraniumSequenceWritesTheFramesTheReadmeStates) {
  const std::string readme = flat_text(source("README.md"));
  const std::smatch c = claim(
      readme,
      "(multiray render \\S*cranium\\S*\\.nhdr [^#`]*-o (\\S+)_(#+)\\.png) # ([0-9]+) frames",
      "the README's cranium command");
  if (c.empty()) return;
  if (!shared_data_here()) GTEST_SKIP() << "../shared/data is absent";
  const Clone clone;
  const auto r = clone.run(c[1]);
  ASSERT_EQ(r.code, 0) << r.out;
  const int digits = int(c[3].length()), stated = std::stoi(c[4]);
  auto frame = [&](int f) {
    std::string n = std::to_string(f);
    return clone.path(c[2].str() + "_" + std::string(size_t(digits) - n.size(), '0') + n + ".png");
  };
  for (int f = 0; f < stated; ++f) EXPECT_TRUE(fs::exists(frame(f))) << "no " << frame(f);
  EXPECT_FALSE(fs::exists(frame(stated))) << "more frames than the README says";
  // "... step at most xS": whatever the machine's speed, frame-time targeting never
  // chose a longer step than the README says (the auto space's bound, balance/targeting.h).
  std::smatch step;
  ASSERT_TRUE(
      std::regex_search(c[0].first, readme.cend(), step, std::regex("step at most x([0-9.]+)")))
      << "the README's cranium line says no bound on the step";
  std::ifstream in(clone.path(c[2].str() + ".stats.json"));
  ASSERT_TRUE(in) << "no " << c[2] << ".stats.json";
  const nlohmann::json stats = nlohmann::json::parse(in);
  ASSERT_EQ(stats.at("frames").size(), size_t(stated));
  for (const nlohmann::json& f : stats.at("frames"))
    EXPECT_LE(f.at("quality").at("step_scale").get<double>(), std::stod(step[1]) + 1e-9)
        << "frame " << f.at("frame");
}

// README.md: "`scripts/break.sh list` shows N deliberate breaks".
TEST(ReadmeFigures, BreakCountIsWhatBreakListShows) {
  const std::string readme = flat_text(source("README.md"));
  const std::smatch m = claim(readme, "`(scripts/break\\.sh list)` shows ([0-9]+) deliberate",
                              "the README's count of breaks");
  if (m.empty()) return;
  const Clone clone;
  const auto r = clone.run(m[1].str());
  ASSERT_EQ(r.code, 0) << r.out;
  // Two lines a break: its name and what it does, then its tests (indented).
  std::istringstream lines(r.out);
  int breaks = 0;
  for (std::string line; std::getline(lines, line);)
    if (!line.empty() && line[0] != ' ') ++breaks;
  EXPECT_EQ(breaks, std::stoi(m[2])) << "README.md says " << m[2] << " breaks";
}

}  // namespace readme_figures_test
