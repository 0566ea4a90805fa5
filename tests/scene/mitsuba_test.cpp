// Mitsuba 3 XML reader (load_mitsuba) on small files written by the test: parameters,
// colours, transforms, references, the sensor's conventions, warnings and errors. The
// real Cornell box is compared with Mitsuba's own render in
// tests/render/mitsuba_reference_test.cpp.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "scene/loaders.h"

namespace multiray {
namespace mitsuba_test {

namespace fs = std::filesystem;

class Mitsuba : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("multiray_mitsuba_" + std::to_string(getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
    options_.warn = [this](const std::string& line) { warnings_.push_back(line); };
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& text) {
    fs::create_directories((dir_ / name).parent_path());
    std::ofstream((dir_ / name).string(), std::ios::binary) << text;
    return (dir_ / name).string();
  }
  // `body` inside <scene>, loaded through load_scene (so the .xml dispatch is tested too).
  Scene load(const std::string& body) {
    return load_scene(write("s.xml", "<scene version=\"3.0.0\">" + body + "</scene>"), options_);
  }
  std::string load_error(const std::string& body) {
    try {
      load(body);
    } catch (const InputError& e) {
      return e.what();
    }
    return "(no error)";
  }
  fs::path dir_;
  LoadOptions options_;
  std::vector<std::string> warnings_;
};

constexpr const char* kQuad = "<shape type=\"rectangle\"/>";

TEST_F(Mitsuba, SensorFovAxisFilmAndHandedness) {
  const Scene s = load(std::string(kQuad) +
                       "<sensor type=\"perspective\"><float name=\"fov\" value=\"60\"/>"
                       "<transform name=\"to_world\"><lookat origin=\"0, 0, -5\" "
                       "target=\"0, 0, 0\" up=\"0, 1, 0\"/></transform>"
                       "<film type=\"hdrfilm\"><integer name=\"width\" value=\"200\"/>"
                       "<integer name=\"height\" value=\"100\"/></film></sensor>");
  ASSERT_EQ(s.cameras.size(), 1u);
  const Camera& c = s.cameras[0];
  EXPECT_NEAR(c.eye.z, -5.0f, 1e-5f);
  const Vec3 forward = normalize(c.target - c.eye);
  EXPECT_NEAR(forward.z, 1.0f, 1e-6f);
  // fov_axis defaults to x: 60 degrees across 200 pixels is 2 atan(tan(30) / 2) down 100.
  EXPECT_NEAR(c.fov_y_deg, 2.0 * std::atan(std::tan(kPi / 6) / 2) * 180 / kPi, 1e-3);
  EXPECT_EQ(c.film_width, 200);
  EXPECT_EQ(c.film_height, 100);
  // Mitsuba shows the look-at frame's +x (up x forward = world +x here) on the image's
  // left. Our pinhole puts forward x up on the right, which must be world -x.
  EXPECT_NEAR(normalize(cross(forward, c.up)).x, -1.0f, 1e-6f);
}

TEST_F(Mitsuba, FovOnSmallerAxisOfAPortraitFilm) {
  const Scene s = load(std::string(kQuad) +
                       "<sensor type=\"perspective\"><float name=\"fov\" value=\"40\"/>"
                       "<string name=\"fov_axis\" value=\"smaller\"/>"
                       "<film type=\"hdrfilm\"><integer name=\"width\" value=\"100\"/>"
                       "<integer name=\"height\" value=\"300\"/></film></sensor>");
  ASSERT_EQ(s.cameras.size(), 1u);  // smaller = x here, so y is three times wider
  EXPECT_NEAR(s.cameras[0].fov_y_deg, 2.0 * std::atan(3 * std::tan(20 * kPi / 180)) * 180 / kPi,
              1e-3);
}

TEST_F(Mitsuba, ParametersColoursTransformsAndForwardReferences) {
  const Scene s = load(
      "<default name=\"g\" value=\"0.5\"/>"
      "<bsdf type=\"twosided\" id=\"paint\"><bsdf type=\"diffuse\">"
      "<rgb name=\"reflectance\" value=\"0.25, $g, 0.75\"/></bsdf></bsdf>"
      "<shape type=\"rectangle\"><ref id=\"paint\"/><ref id=\"lamp\"/>"
      "<transform name=\"to_world\"><scale value=\"2\"/><rotate x=\"1\" angle=\"90\"/>"
      "<translate x=\"10\" y=\"0\" z=\"0\"/></transform></shape>"
      "<emitter type=\"area\" id=\"lamp\"><rgb name=\"radiance\" value=\"1, 2, 3\"/></emitter>");
  ASSERT_EQ(s.triangle_count(), 2u);
  ASSERT_EQ(s.materials.size(), 1u);
  EXPECT_NEAR(s.materials[0].base_color.y, 0.5f, 1e-6f);
  EXPECT_NEAR(s.materials[0].base_color.z, 0.75f, 1e-6f);
  EXPECT_NEAR(s.materials[0].emission.z, 3.0f, 1e-6f);
  // Scaled to [-2, 2]^2, turned 90 degrees about x (the plane z = 0 becomes y = 0), moved.
  const Bounds3 b = s.bounds();
  EXPECT_NEAR(b.lo.x, 8.0f, 1e-5f);
  EXPECT_NEAR(b.hi.x, 12.0f, 1e-5f);
  EXPECT_NEAR(b.hi.y - b.lo.y, 0.0f, 1e-5f);
  EXPECT_NEAR(b.hi.z - b.lo.z, 4.0f, 1e-5f);
  EXPECT_TRUE(warnings_.empty()) << warnings_.front();
}

TEST_F(Mitsuba, SpectraBecomeLinearSrgb) {
  const Scene s = load(
      "<shape type=\"rectangle\"><bsdf type=\"diffuse\">"
      "<spectrum name=\"reflectance\" value=\"360:0.5, 830:0.5\"/></bsdf></shape>"
      "<shape type=\"cube\"><bsdf type=\"diffuse\"><spectrum name=\"reflectance\" "
      "value=\"400:0.05, 580:0.05, 600:0.6, 700:0.6\"/></bsdf>"
      "<emitter type=\"area\"><spectrum name=\"radiance\" value=\"360:1, 830:1\"/>"
      "</emitter></shape>");
  ASSERT_EQ(s.materials.size(), 2u);
  const Vec3 grey = s.materials[0].base_color, red = s.materials[1].base_color;
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(grey[k], 0.5f, 1e-3f) << k;  // flat: neutral
  EXPECT_GT(red.x, 0.3f);
  EXPECT_LT(red.y, 0.15f);
  EXPECT_LT(red.z, 0.1f);
  // A flat radiance spectrum of 1 has luminance 1 (equal-energy white, slightly pink).
  EXPECT_NEAR(luminance(s.materials[1].emission), 1.0f, 0.01f);
  EXPECT_GT(s.materials[1].emission.x, s.materials[1].emission.z);
}

TEST_F(Mitsuba, CubeFacesOutwards) {
  const Scene s = load("<shape type=\"cube\"/>");
  ASSERT_EQ(s.triangle_count(), 12u);
  for (size_t t = 0; t < 12; ++t) {
    const Vec3 a = s.positions[s.indices[3 * t]], b = s.positions[s.indices[3 * t + 1]],
               c = s.positions[s.indices[3 * t + 2]];
    EXPECT_GT(dot(cross(b - a, c - a), a + b + c), 0.0f) << "triangle " << t;
  }
}

TEST_F(Mitsuba, UnsupportedTypesWarnOncePerType) {
  const Scene s = load(std::string(kQuad) +
                       "<shape type=\"sphere\"/><shape type=\"sphere\"/>"
                       "<shape type=\"rectangle\"><bsdf type=\"roughplastic\"/></shape>"
                       "<emitter type=\"point\"/>");
  EXPECT_EQ(s.triangle_count(), 4u);
  ASSERT_EQ(warnings_.size(), 3u);
  EXPECT_NE(warnings_[0].find("sphere"), std::string::npos) << warnings_[0];
  EXPECT_NE(warnings_[1].find("roughplastic"), std::string::npos) << warnings_[1];
  EXPECT_NE(warnings_[2].find("point"), std::string::npos) << warnings_[2];
}

TEST_F(Mitsuba, BadFilesAreOneLineInputErrors) {
  for (const std::string& body : {
           std::string("<shape type=\"rectangle\">"),  // malformed
           std::string("<shape type=\"obj\"><string name=\"filename\" value=\"$nope.obj\"/>"
                       "</shape>"),
           std::string("<shape type=\"obj\"><string name=\"filename\" value=\"no.obj\"/>"
                       "</shape>"),
           std::string("<shape type=\"rectangle\"><ref id=\"missing\"/></shape>"),
           std::string(kQuad) + "<sensor type=\"perspective\"><transform name=\"to_world\">"
                                "<translate value=\"1, x, 2\"/></transform></sensor>",
       }) {
    const std::string e = load_error(body);
    EXPECT_NE(e.find("s.xml: "), std::string::npos) << body << " -> " << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  }
  EXPECT_NE(load_error("<shape type=\"rectangle\">").find("malformed XML"), std::string::npos);
}

TEST_F(Mitsuba, MeshesThroughPathsStayInsideTheFolderUnlessAllowed) {
  write("meshes/tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  const std::string inside =
      write("s.xml",
            "<scene version=\"3.0.0\"><path value=\"meshes\"/><shape type=\"obj\">"
            "<string name=\"filename\" value=\"tri.obj\"/></shape></scene>");
  EXPECT_EQ(load_scene(inside, options_).triangle_count(), 1u);
  const std::string outside =
      write("sub/s.xml",
            "<scene version=\"3.0.0\"><path value=\"../meshes\"/><shape type=\"obj\">"
            "<string name=\"filename\" value=\"tri.obj\"/></shape></scene>");
  EXPECT_THROW(load_scene(outside, options_), InputError);
  options_.allow_outside = true;
  EXPECT_EQ(load_scene(outside, options_).triangle_count(), 1u);
}

}  // namespace mitsuba_test
}  // namespace multiray
