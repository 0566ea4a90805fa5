// The messages between ranks and the emulated link, without MPI: every message survives
// a round trip, no truncated or inflated message is accepted, and the link model charges
// latency and bandwidth as Seo et al.'s shared master link does.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <type_traits>
#include <vector>

#include "core/error.h"
#include "distributed/link.h"
#include "distributed/pixel_codec.h"
#include "distributed/protocol.h"
#include "distributed/wire.h"

namespace multiray::remote {
namespace protocol_test {

FrameMessage sample_frame() {
  FrameMessage m;
  m.epoch = 7;
  m.settings.spp = 3, m.settings.max_bounces = 5, m.settings.seed = 99;
  m.settings.kernel = "ao", m.settings.step_scale = 0.5f, m.settings.sample_clamp = 4;
  ViewSetup v;
  v.camera.eye = {1, 2, 3}, v.camera.fov_y_deg = 30;
  v.width = 4, v.height = 2, v.view = 1, v.frame = 12;
  v.first_sample = 48, v.sample_frame = 9;  // a progressive frame (render_settings.h)
  m.views = {v, v};
  m.spp_maps = {{}, {1, 2, 3, 4, 5, 6, 7, 8}};
  return m;
}

// The frame sample_result() belongs to: two views of 4x2.
const ResultBounds kBounds{4, 2, 2};

ResultMessage sample_result() {
  ResultMessage m;
  m.epoch = 3;
  ItemResult it;
  it.report.id = 5;
  it.report.item = WorkItem{Rect{1, 1, 3, 2}, 1};
  it.report.time_ms = 2.5, it.report.busy_ms = 2, it.report.samples = 8;
  it.rays = 40;
  it.pixels = {{1, 2, 3}, {4, 5, 6}};
  m.items = {it};
  m.local = {{1.5, 1.0}, {2.5, 2.0}};
  return m;
}

TEST(Protocol, MessagesSurviveARoundTrip) {
  const FrameMessage f = decode_frame(encode(sample_frame()));
  EXPECT_EQ(f.epoch, 7u);
  EXPECT_EQ(f.settings.kernel, "ao");
  EXPECT_EQ(f.settings.seed, 99u);
  EXPECT_FLOAT_EQ(f.settings.step_scale, 0.5f);
  EXPECT_EQ(f.settings.sample_clamp, 4.0f);
  ASSERT_EQ(f.views.size(), 2u);
  EXPECT_EQ(f.views[1].frame, 12u);
  EXPECT_EQ(f.views[1].first_sample, 48u);
  EXPECT_EQ(f.views[1].seed_frame(), 9u);
  EXPECT_FLOAT_EQ(f.views[1].camera.eye.y, 2);
  EXPECT_EQ(f.spp_maps[1].size(), 8u);

  WorkMessage w{4, true, {9, 10}, {WorkItem{Rect{0, 0, 2, 2}, 0}, WorkItem{Rect{2, 0, 4, 2}, 1}}};
  const WorkMessage w2 = decode_work(encode(w));
  EXPECT_TRUE(w2.batched);
  EXPECT_EQ(w2.ids, w.ids);
  EXPECT_EQ(w2.items, w.items);

  const ResultMessage r = decode_result(encode(sample_result()), kBounds);
  ASSERT_EQ(r.items.size(), 1u);
  EXPECT_EQ(r.items[0].report.item, (WorkItem{Rect{1, 1, 3, 2}, 1}));
  EXPECT_FLOAT_EQ(r.items[0].pixels[1].z, 6);
  EXPECT_EQ(r.items[0].rays, 40u);
  EXPECT_DOUBLE_EQ(r.local[1].time_ms, 2.5);

  HelloMessage h;
  h.devices.push_back(DeviceInfo{"cpu",
                                 "cpu (1 thread)",
                                 "cpu:threads=1",
                                 1,
                                 0.5,
                                 0,
                                 {{"path"}, {"uniform"}, "embree"},
                                 "embree",
                                 0,
                                 0,
                                 {}});
  h.fingerprint = {{"'a.obj'", 0x0123456789abcdefull}, {"the scene options (--env 0.3)", 0}};
  const HelloMessage h2 = decode_hello(encode(h));
  ASSERT_EQ(h2.fingerprint.size(), 2u);
  EXPECT_EQ(h2.fingerprint[0].what, "'a.obj'");
  EXPECT_EQ(h2.fingerprint[0].hash, 0x0123456789abcdefull);
  EXPECT_EQ(h2.fingerprint[1].what, "the scene options (--env 0.3)");
  ASSERT_EQ(h2.devices.size(), 1u);
  EXPECT_EQ(h2.devices[0].caps.kernels, std::vector<std::string>{"path"});
  EXPECT_DOUBLE_EQ(h2.devices[0].emulated_speed, 0.5);
  EXPECT_EQ(decode_failure(encode(FailureMessage{2, "lost"})).error, "lost");
  EXPECT_DOUBLE_EQ(decode_speed(encode_speed(0.25)), 0.25);
  EXPECT_TRUE(decode_quit(encode_quit(true)));
  EXPECT_FALSE(decode_quit(encode_quit(false)));
}

// Feature buffers (--aov) ride with the pixels, in every result encoding: the lossless
// ones give back the very floats (an infinite depth too), half rounds as the pixels do;
// a result without them stays without, and a payload of the wrong size is refused.
TEST(Protocol, FeatureBuffersTravelWithThePixels) {
  ResultMessage m = sample_result();
  m.items[0].features = {0.5f, 0.25f, 0.125f, 0, 1, 0, INFINITY, 1e-3f, 3.0f, 2.0f, 1.0f,
                         0.1f, 0.2f,  0.3f,   1, 0, 0, 2.5f,     0.0f,  0.0f, 0.0f, 0.0f};
  for (const ResultEncoding e : {ResultEncoding::float32, ResultEncoding::float_zstd,
                                 ResultEncoding::half, ResultEncoding::half_zstd}) {
    if (uses_zstd(e) && !zstd_available()) continue;
    m.encoding = e;
    const std::vector<float> got = decode_result(encode(m), kBounds).items.at(0).features;
    ASSERT_EQ(got.size(), m.items[0].features.size());
    for (size_t i = 0; i < got.size(); ++i)
      EXPECT_EQ(got[i],
                is_lossy(e) ? round_to_half(m.items[0].features[i]) : m.items[0].features[i])
          << i << " " << result_encoding_name(e);
  }
  EXPECT_TRUE(decode_result(encode(sample_result()), kBounds).items[0].features.empty());
  m.encoding = ResultEncoding::float32;
  m.items[0].features.pop_back();
  EXPECT_THROW(decode_result(encode(m), kBounds), WireError);
}

// The master's comparison with a worker's fingerprint (issue 53): equal lists pass; a file
// whose content differs is named with both hashes; other options or files are shown.
TEST(Fingerprint, TheFirstDifferenceIsNamed) {
  const PixelFingerprint mine = {{"'a.obj'", 1}, {"'a.mtl'", 2}, {"options (--env 0.3)", 0}};
  EXPECT_EQ(fingerprint_difference(mine, mine), "");
  PixelFingerprint other = mine;
  other[1].hash = 3;
  EXPECT_EQ(fingerprint_difference(mine, other),
            "'a.mtl' differs (content hash 0000000000000002 here, 0000000000000003 there)");
  other = mine;
  other[2].what = "options (--env sky.hdr)";
  EXPECT_EQ(fingerprint_difference(mine, other),
            "options (--env 0.3) here, options (--env sky.hdr) there");
  other = mine;
  other.pop_back();
  EXPECT_EQ(fingerprint_difference(mine, other), "options (--env 0.3) here, nothing more there");
  EXPECT_EQ(fingerprint_difference(other, mine), "options (--env 0.3) there, nothing more here");
}

// Every setting for_each_sent_setting lists travels: each one changed from its default on
// its own arrives changed, and nothing else does. (A field missing from the list entirely
// stops protocol.cpp from compiling; see render/render_settings.h.)
TEST(Protocol, EverySentSettingTravels) {
  const RenderSettings defaults;
  std::vector<std::string> names;
  for_each_sent_setting(defaults, [&](const char* name, const auto&) { names.push_back(name); });
  EXPECT_EQ(names.size(), kSentSettings);
  for (size_t k = 0; k < names.size(); ++k) {
    FrameMessage m = sample_frame();
    m.settings = RenderSettings{};
    size_t i = 0;
    // Field k gets a value unlike its default (and valid on the wire).
    for_each_sent_setting(m.settings, [&](const char* name, auto& v) {
      using T = std::decay_t<decltype(v)>;
      if (i++ != k) return;
      if constexpr (std::is_same_v<T, std::string>)
        v = "depth";
      else if constexpr (std::is_same_v<T, bool>)
        v = !v;
      else if (std::string(name) == "catcher_albedo")  // an albedo stays within [0, 1]
        v = T(0.25);
      else
        v = v + T(2);
    });
    const RenderSettings got = decode_frame(encode(m)).settings;
    size_t j = 0;
    for_each_sent_setting(got, [&](const char* name, const auto& v) {
      const size_t at = j++;
      size_t n = 0;
      for_each_sent_setting(at == k ? m.settings : defaults, [&](const char*, const auto& w) {
        if constexpr (std::is_same_v<std::decay_t<decltype(w)>, std::decay_t<decltype(v)>>) {
          if (n == at) {
            EXPECT_EQ(v, w) << name << " (changed: " << names[k] << ")";
          }
        }
        ++n;
      });
    });
  }
}

TEST(Protocol, EveryTruncationIsRefused) {
  const std::vector<uint8_t> frame = encode(sample_frame()), result = encode(sample_result());
  for (size_t n = 0; n < frame.size(); ++n)
    EXPECT_THROW(decode_frame(std::vector<uint8_t>(frame.begin(), frame.begin() + n)), WireError)
        << n;
  for (size_t n = 0; n < result.size(); ++n)
    EXPECT_THROW(decode_result(std::vector<uint8_t>(result.begin(), result.begin() + n), kBounds),
                 WireError)
        << n;
}

TEST(Protocol, ImpossibleValuesAreRefused) {
  ResultMessage r = sample_result();
  r.items[0].pixels.pop_back();  // fewer pixels than the rect holds
  EXPECT_THROW(decode_result(encode(r), kBounds), WireError);
  FrameMessage f = sample_frame();
  f.spp_maps[1].pop_back();  // a sample map of the wrong size
  EXPECT_THROW(decode_frame(encode(f)), WireError);
  f = sample_frame();
  f.views[0].width = 0;
  EXPECT_THROW(decode_frame(encode(f)), WireError);
  for (float clamp : {-1.0f, NAN, INFINITY}) {
    f = sample_frame();
    f.settings.sample_clamp = clamp;  // --clamp refuses these; a worker must too
    EXPECT_THROW(decode_frame(encode(f)), WireError) << clamp;
  }
  WorkMessage w{1, false, {1}, {WorkItem{Rect{3, 0, 2, 2}, 0}}};  // x1 < x0
  EXPECT_THROW(decode_work(encode(w)), WireError);
  EXPECT_THROW(decode_speed(encode_speed(0)), WireError);
  EXPECT_THROW(decode_quit({}), WireError);
  EXPECT_THROW(decode_quit({2}), WireError);
  // A count far beyond the message's length must not allocate.
  ByteWriter big;
  big.put(uint32_t(1)), big.put(uint8_t(0)), big.put(uint64_t(1) << 60);
  EXPECT_THROW(decode_result(big.take(), kBounds), WireError);
}

TEST(Link, PresetsAndCustomLinks) {
  EXPECT_FALSE(parse_link("none").active());
  const LinkSpec wifi = parse_link("wifi");
  EXPECT_DOUBLE_EQ(wifi.latency_ms, 5);
  EXPECT_DOUBLE_EQ(wifi.mbit_per_s, 200);
  EXPECT_TRUE(wifi.shared);
  EXPECT_THAT(wifi.describe(), ::testing::HasSubstr("emulated"));
  const LinkSpec lan = parse_link("lan");
  EXPECT_DOUBLE_EQ(lan.latency_ms, 0.1);
  EXPECT_DOUBLE_EQ(lan.mbit_per_s, 10000);
  const LinkSpec custom = parse_link("2,50,separate");
  EXPECT_FALSE(custom.shared);
  for (const char* bad : {"fast", "1", "1,2,3", "-1,5", "1,x", "1,2,shared", "nan,1", "1,1e9"})
    EXPECT_THROW(parse_link(bad), std::invalid_argument) << bad;
}

TEST(Link, SharedMasterLinkSerialisesMessagesAndAddsLatency) {
  using Clock = LinkModel::Clock;
  const auto ms = [](double x) {
    return std::chrono::duration_cast<Clock::duration>(
        std::chrono::duration<double, std::milli>(x));
  };
  const Clock::time_point t0{};
  // 1 Mbit/s: 125 bytes take 1 ms; latency 5 ms.
  LinkModel shared(LinkSpec{"test", 5, 1, true}, 2);
  EXPECT_EQ(shared.deliver_at(0, 125, t0), t0 + ms(6));
  // Worker 1's message waits for worker 0's on the shared link.
  EXPECT_EQ(shared.deliver_at(1, 125, t0), t0 + ms(7));
  LinkModel separate(LinkSpec{"test", 5, 1, false}, 2);
  EXPECT_EQ(separate.deliver_at(0, 125, t0), t0 + ms(6));
  EXPECT_EQ(separate.deliver_at(1, 125, t0), t0 + ms(6));
  // A free link: latency only.
  EXPECT_EQ(separate.deliver_at(1, 0, t0 + ms(100)), t0 + ms(105));
  LinkModel none(LinkSpec{}, 2);
  EXPECT_EQ(none.deliver_at(0, 1 << 20, t0), t0);
}

}  // namespace protocol_test
}  // namespace multiray::remote
