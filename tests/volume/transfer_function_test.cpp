// Transfer functions: the JSON format (good and bad), presets, resolving fractions,
// evaluation, the baked table and the opacity correction.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "scene/load_guard.h"
#include "volume/transfer_function.h"
#include "volume/volume_test_files.h"

namespace multiray {
namespace transfer_function_test {

using test::expect_input_error;
using test::within_10s;

Volume ct_like() {
  Volume v;
  v.nx = v.ny = v.nz = 1;
  v.values = {0};
  v.min_value = -1024;
  v.max_value = 2976;
  return v;
}

TEST(TransferJson, ReadsPointsUnitsAndOptionalKeys) {
  const TransferFunction tf = parse_transfer_function(
      R"({"name": "t", "units": "fraction", "reference_step": 2,
          "points": [{"value": 0, "color": [0, 0, 0], "opacity": 0},
                     {"value": 0.5, "color": [1, 0.5, 0], "opacity": 0.25},
                     {"value": 1, "color": [1, 1, 1], "opacity": 1}]})",
      "t.json");
  EXPECT_EQ(tf.name, "t");
  EXPECT_EQ(tf.units, TfUnits::fraction);
  EXPECT_EQ(tf.reference_step, 2);
  ASSERT_EQ(tf.points.size(), 3u);
  EXPECT_EQ(tf.points[1].color.y, 0.5f);
  EXPECT_EQ(tf.points[1].opacity, 0.25f);
  const TransferFunction r = resolve(tf, ct_like());
  EXPECT_EQ(r.units, TfUnits::data);
  EXPECT_EQ(r.points[0].value, -1024);
  EXPECT_EQ(r.points[1].value, 976);
  EXPECT_EQ(r.points[2].value, 2976);
  // Data units are the default and resolve to themselves.
  const TransferFunction d = parse_transfer_function(
      R"({"points": [{"value": -1024, "color": [0, 0, 0], "opacity": 0},
                     {"value": 3000, "color": [1, 1, 1], "opacity": 1}]})",
      "d.json");
  EXPECT_EQ(d.units, TfUnits::data);
  EXPECT_EQ(resolve(d, ct_like()).points[1].value, 3000);
}

TEST(TransferJson, BadFunctionsAreOneLineEach) {
  auto bad = [](const std::string& points, std::initializer_list<std::string> words,
                const std::string& extra = "") {
    const std::string json = "{" + extra + R"("points": [)" + points + "]}";
    expect_input_error(within_10s([json] { parse_transfer_function(json, "f.json"); }), words);
  };
  const std::string a = R"({"value": 0, "color": [0, 0, 0], "opacity": 0})";
  const std::string b = R"({"value": 1, "color": [1, 1, 1], "opacity": 1})";
  bad(a, {"f.json", "2..4096 points, not 1"});
  bad(b + "," + a, {"point 1", "below the previous value"});
  bad(a + "," + a, {"point 1", "repeats the previous value"});
  bad(a + R"(, {"value": 1, "color": [1, 2, 1], "opacity": 1})", {"point 1", "color"});
  bad(a + R"(, {"value": 1, "color": [1, 1], "opacity": 1})", {"color"});
  bad(a + R"(, {"value": 1, "color": [1, 1, 1], "opacity": 1.5})", {"opacity"});
  bad(a + R"(, {"value": 1e39, "color": [1, 1, 1], "opacity": 1})", {"value", "finite"});
  bad(a + R"(, {"value": "1", "color": [1, 1, 1], "opacity": 1})", {"value"});
  bad(a + R"(, {"value": 1, "colour": [1, 1, 1], "opacity": 1})", {"unknown key 'colour'"});
  bad(a + R"(, {"value": 1, "color": [1, 1, 1]})", {"\"opacity\" is missing"});
  bad(a + "," + b, {"unknown key 'gamma'"}, R"("gamma": 2, )");
  bad(a + "," + b, {"units must be"}, R"("units": "hu", )");
  bad(a + "," + b, {"reference_step"}, R"("reference_step": 0, )");
  bad(a + R"(, {"value": 2, "color": [1, 1, 1], "opacity": 1})", {"fraction", "[0, 1]"},
      R"("units": "fraction", )");
  expect_input_error(within_10s([] { parse_transfer_function("{\"points\": [", "j.json"); }),
                     {"j.json", "not valid JSON"});
  expect_input_error(within_10s([] { parse_transfer_function("[1, 2]", "k.json"); }),
                     {"JSON object"});
}

class TransferFile : public test::VolumeFiles {};

TEST_F(TransferFile, LoadsRegularFilesWithinTheLimitOnly) {
  const std::string ok = write("vol/tf.json", R"({"points": [
      {"value": 0, "color": [0, 0, 0], "opacity": 0},
      {"value": 10, "color": [1, 1, 1], "opacity": 0.5}]})");
  const TransferFunction tf = load_transfer_function(ok);
  EXPECT_EQ(tf.name, "tf.json");
  EXPECT_EQ(tf.points[1].opacity, 0.5f);
  const std::string f = fifo("vol/fifo.json");
  expect_input_error(within_10s([f] { load_transfer_function(f); }), {"not a regular file"});
  const std::string big = write("vol/big.json", std::string(kMaxTfFileBytes + 1, ' '));
  expect_input_error(within_10s([big] { load_transfer_function(big); }), {"big.json", "limit"});
}

TEST(TransferPresets, ExistAndResolve) {
  const Volume v = ct_like();
  ASSERT_GE(transfer_preset_names().size(), 4u);
  for (const std::string& name : transfer_preset_names()) {
    const TransferFunction tf = transfer_preset(name, v);
    EXPECT_EQ(tf.name, name);
    EXPECT_EQ(tf.units, TfUnits::data);
    EXPECT_NO_THROW(check_transfer_function(tf, name));
  }
  // Soft tissue: transparent below the window (-221 HU), visible inside it.
  const TransferFunction soft = transfer_preset("ct-soft-tissue", v);
  EXPECT_EQ(evaluate(soft, -500)[3], 0);
  EXPECT_GT(evaluate(soft, 40)[3], 0);
  // Bone: nothing below 250 HU, opaque-ish bone.
  const TransferFunction bone = transfer_preset("ct-bone", v);
  EXPECT_EQ(max_opacity(bone, -1024, 250), 0);
  EXPECT_GT(evaluate(bone, 700)[3], 0.3f);
  // Fraction presets span the volume's range; the minimum is transparent.
  const TransferFunction grey = transfer_preset("grey", v);
  EXPECT_EQ(grey.points.front().value, -1024);
  EXPECT_EQ(grey.points.back().value, 2976);
  EXPECT_EQ(evaluate(transfer_preset("angio", v), -1024)[3], 0);
  expect_input_error(within_10s([v] { transfer_preset("bones", v); }),
                     {"'bones'", "ct-bone", "ct-soft-tissue", "angio", "grey"});
}

TEST(TransferEval, PiecewiseLinearClampedAndExactMaximum) {
  TransferFunction tf;
  tf.points = {{0, {0, 0, 0}, 0}, {10, {1, 0.5f, 0}, 1}, {20, {0, 0, 1}, 0}};
  EXPECT_EQ(evaluate(tf, 5)[3], 0.5f);
  EXPECT_EQ(evaluate(tf, 5)[1], 0.25f);
  EXPECT_EQ(evaluate(tf, -100)[3], 0);
  EXPECT_EQ(evaluate(tf, 100)[2], 1);
  EXPECT_EQ(evaluate(tf, NAN)[3], 0);
  EXPECT_EQ(max_opacity(tf, 2, 18), 1);  // the interior point
  EXPECT_EQ(max_opacity(tf, 12, 18), 0.8f);
  EXPECT_EQ(max_opacity(tf, 20, 30), 0);
}

TEST(TransferTable, BakedEntriesInterpolateAndClamp) {
  TransferFunction tf;
  tf.points = {{0, {0, 0, 0}, 0}, {100, {1, 1, 1}, 1}};
  const TransferTable t = bake(tf, 0, 100, 101);
  ASSERT_EQ(t.rgba.size(), 101u);
  EXPECT_FLOAT_EQ(t.rgba[50][3], 0.5f);
  EXPECT_FLOAT_EQ(t.lookup(25.5f)[3], 0.255f);
  EXPECT_EQ(t.lookup(-5)[3], 0);
  EXPECT_EQ(t.lookup(1e30f)[3], 1);
  EXPECT_EQ(t.lookup(NAN)[3], 0);
  // A table over a narrower range clamps to its ends.
  const TransferTable n = bake(tf, 20, 40, 3);
  EXPECT_FLOAT_EQ(n.lookup(30)[0], 0.3f);
  EXPECT_FLOAT_EQ(n.lookup(0)[0], 0.2f);
  EXPECT_FLOAT_EQ(n.lookup(100)[0], 0.4f);
  EXPECT_EQ(bake(tf, 7, 7, 2).hi, 8);  // constant volume
  EXPECT_THROW(bake(tf, 0, INFINITY, 16), std::invalid_argument);
  EXPECT_THROW(bake(tf, 0, 1, 1), std::invalid_argument);
}

TEST(TransferTable, OpacityCorrection) {
  EXPECT_FLOAT_EQ(corrected_alpha(0.5f, 2), 0.75f);
  EXPECT_EQ(corrected_alpha(0.3f, 1), 0.3f);
  EXPECT_FLOAT_EQ(corrected_alpha(0.75f, 0.5f), 0.5f);
  EXPECT_EQ(corrected_alpha(0, 3), 0);
  EXPECT_EQ(corrected_alpha(1, 0.01f), 1);
  EXPECT_EQ(corrected_alpha(0.5f, 0), 0);
  EXPECT_EQ(corrected_alpha(2, 1), 1);  // clamped
  EXPECT_EQ(corrected_alpha(NAN, 1), 0);
}

}  // namespace transfer_function_test
}  // namespace multiray
