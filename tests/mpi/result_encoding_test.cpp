// --result-encoding: a worker's pixels survive the trip to the master in every encoding
// (bit for bit in the lossless ones, rounded to the nearest half in the lossy ones), the
// half conversion is IEEE's round to nearest even with subnormals, infinities and NaN,
// and no hostile Result makes the master crash or allocate beyond its frame.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "distributed/link.h"
#include "distributed/pixel_codec.h"
#include "distributed/protocol.h"
#include "distributed/wire.h"

namespace multiray::remote {
namespace result_encoding_test {

constexpr ResultEncoding kAll[] = {ResultEncoding::float32, ResultEncoding::half,
                                   ResultEncoding::float_zstd, ResultEncoding::half_zstd};

bool available(ResultEncoding e) { return !uses_zstd(e) || zstd_available(); }

// The nearest half to `v` by search over every finite half (ties to the even one), after
// clamping finite values to +-65504: an independent reference for half_bits.
uint16_t reference_half(float v) {
  if (std::isnan(v)) return 0x7e00;
  const uint16_t sign = std::signbit(v) ? 0x8000 : 0;
  if (std::isinf(v)) return sign | 0x7c00;
  const double a = std::min(std::fabs(double(v)), 65504.0);
  uint16_t lo = 0, hi = 0x7bff;  // positive finite halves, ascending with their bits
  while (lo < hi) {              // the largest half <= a
    const uint16_t mid = uint16_t((lo + hi + 1) / 2);
    if (double(half_value(mid)) <= a)
      lo = mid;
    else
      hi = uint16_t(mid - 1);
  }
  if (lo == 0x7bff || double(half_value(lo)) == a) return sign | lo;
  const double below = a - half_value(lo), above = half_value(uint16_t(lo + 1)) - a;
  if (below < above || (below == above && (lo & 1) == 0)) return sign | lo;
  return sign | uint16_t(lo + 1);
}

TEST(HalfConversion, EveryHalfSurvivesAndEveryTieGoesToEven) {
  for (uint32_t b = 0; b < 0x7c00; ++b) {  // every finite positive half, subnormals included
    const uint16_t h = uint16_t(b);
    ASSERT_EQ(half_bits(half_value(h)), h) << b;
    ASSERT_EQ(half_bits(-half_value(h)), h | 0x8000) << b;
    if (b + 1 == 0x7c00) break;
    // Halfway to the next half (exact in a float): to whichever of the two is even.
    const float mid = float((double(half_value(h)) + half_value(uint16_t(h + 1))) / 2);
    ASSERT_EQ(half_bits(mid), (h & 1) ? h + 1 : h) << b;
    // Just either side of halfway: the nearer one.
    ASSERT_EQ(half_bits(std::nextafter(mid, 0.0f)), h) << b;
    ASSERT_EQ(half_bits(std::nextafter(mid, 1e9f)), h + 1) << b;
  }
}

TEST(HalfConversion, SpecialValuesAndClamping) {
  EXPECT_EQ(half_bits(0.0f), 0x0000);
  EXPECT_EQ(half_bits(-0.0f), 0x8000);
  EXPECT_EQ(half_value(0x0001), std::ldexp(1.0f, -24));  // the smallest subnormal
  EXPECT_EQ(half_bits(std::ldexp(1.0f, -25)), 0x0000);   // a tie with 0: even
  EXPECT_EQ(half_bits(std::ldexp(1.5f, -25)), 0x0001);
  EXPECT_EQ(half_bits(std::ldexp(1.0f, -30)), 0x0000);  // underflows to zero
  EXPECT_EQ(half_bits(1.0f), 0x3c00);
  EXPECT_EQ(round_to_half(0.1f), 0.0999755859375f);
  EXPECT_EQ(half_bits(INFINITY), 0x7c00);
  EXPECT_EQ(half_bits(-INFINITY), 0xfc00);
  EXPECT_TRUE(std::isnan(round_to_half(NAN)));
  EXPECT_TRUE(std::isinf(half_value(0x7c00)));
  // Finite values past the largest half clamp to it instead of becoming infinite.
  for (float big : {65504.0f, 65519.0f, 65520.0f, 1e6f, 3e38f}) {
    EXPECT_EQ(round_to_half(big), 65504.0f) << big;
    EXPECT_EQ(round_to_half(-big), -65504.0f) << big;
  }
}

TEST(HalfConversion, MatchesTheReferenceOnRandomFloats) {
  std::mt19937 rng(30);
  for (int i = 0; i < 200000; ++i) {
    const float v = std::bit_cast<float>(uint32_t(rng()));
    if (std::isnan(v)) continue;
    ASSERT_EQ(half_bits(v), reference_half(v)) << v;
  }
}

// Pixels like a rendered tile: smooth, with noise, black, very bright and special values.
std::vector<Vec3> sample_pixels(size_t n) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> noise(0, 0.05f);
  std::vector<Vec3> px(n);
  for (size_t i = 0; i < n; ++i) {
    const float t = float(i) / float(n);
    px[i] = {t + noise(rng), 0.5f * t, i % 7 == 0 ? 0.0f : 2 * t + noise(rng)};
  }
  if (n >= 6) {
    px[1] = {INFINITY, -INFINITY, NAN};
    px[2] = {1e-30f, std::ldexp(1.0f, -20), -0.0f};
    px[3] = {1e6f, 70000.0f, 65504.0f};
  }
  return px;
}

bool same_bits(float a, float b) {
  return std::bit_cast<uint32_t>(a) == std::bit_cast<uint32_t>(b);
}

TEST(ResultEncoding, EveryEncodingRoundTrips) {
  const std::vector<Vec3> px = sample_pixels(64 * 48);
  for (ResultEncoding e : kAll) {
    if (!available(e)) continue;
    ByteWriter w;
    put_pixels(w, px, e);
    const std::vector<uint8_t> bytes = w.take();
    ByteReader r(bytes);
    const std::vector<Vec3> got = get_pixels(r, e, px.size());
    EXPECT_TRUE(r.done());
    ASSERT_EQ(got.size(), px.size());
    for (size_t i = 0; i < px.size(); ++i)
      for (int c = 0; c < 3; ++c) {
        const float want = is_lossy(e) ? round_to_half(px[i][c]) : px[i][c];
        if (std::isnan(want)) {
          ASSERT_TRUE(std::isnan(got[i][c])) << result_encoding_name(e) << " " << i;
        } else {
          ASSERT_TRUE(same_bits(got[i][c], want))
              << result_encoding_name(e) << " pixel " << i << "." << c << ": " << got[i][c]
              << " for " << want;
        }
      }
    if (!uses_zstd(e)) {
      EXPECT_EQ(bytes.size(), 8 + px.size() * raw_bytes_per_pixel(e));
    }
  }
}

// A half-encoded frame is the same whatever the split: each pixel is rounded on its own.
TEST(ResultEncoding, HalfRoundingDoesNotDependOnTheSplit) {
  const std::vector<Vec3> px = sample_pixels(1000);
  for (ResultEncoding e : {ResultEncoding::half, ResultEncoding::half_zstd}) {
    if (!available(e)) continue;
    std::vector<Vec3> whole, parts;
    for (const auto& [from, to] : {std::pair<size_t, size_t>{0, 1000}, {0, 333}, {333, 1000}}) {
      ByteWriter w;
      put_pixels(w, std::vector<Vec3>(px.begin() + long(from), px.begin() + long(to)), e);
      const std::vector<uint8_t> bytes = w.take();
      ByteReader r(bytes);
      const std::vector<Vec3> got = get_pixels(r, e, to - from);
      (to - from == 1000 ? whole : parts)
          .insert((to - from == 1000 ? whole : parts).end(), got.begin(), got.end());
    }
    ASSERT_EQ(whole.size(), parts.size());
    for (size_t i = 0; i < whole.size(); ++i)
      for (int c = 0; c < 3; ++c)
        EXPECT_TRUE(same_bits(whole[i][c], parts[i][c]) || std::isnan(whole[i][c])) << i;
  }
}

TEST(ResultEncoding, ResultMessagesCarryTheirEncoding) {
  for (ResultEncoding e : kAll) {
    if (!available(e)) continue;
    ResultMessage m;
    m.epoch = 2, m.encoding = e;
    ItemResult it;
    it.report.item = WorkItem{Rect{0, 0, 8, 4}, 1};
    it.pixels = sample_pixels(32);
    m.items = {it};
    const std::vector<uint8_t> bytes = encode(m);
    const ResultMessage got = decode_result(bytes, ResultBounds{8, 4, 2});
    EXPECT_EQ(got.encoding, e);
    ASSERT_EQ(got.items.size(), 1u);
    EXPECT_EQ(got.items[0].pixels[5].x,
              is_lossy(e) ? round_to_half(it.pixels[5].x) : it.pixels[5].x);
    for (size_t n = 0; n < bytes.size(); ++n)  // every truncation is refused
      ASSERT_THROW(decode_result(std::vector<uint8_t>(bytes.begin(), bytes.begin() + long(n)),
                                 ResultBounds{8, 4, 2}),
                   WireError)
          << result_encoding_name(e) << " " << n;
  }
}

// The Frame message carries the master's --result-encoding to the worker.
TEST(ResultEncoding, TheFrameCarriesTheEncoding) {
  FrameMessage f;
  ViewSetup v;
  v.width = 4, v.height = 2;
  f.views = {v};
  f.spp_maps = {{}};
  for (ResultEncoding e : kAll) {
    f.results = e;
    EXPECT_EQ(decode_frame(encode(f)).results, e) << result_encoding_name(e);
  }
  std::vector<uint8_t> bytes = encode(f);
  bytes.back() = kResultEncodings;  // the encoding is the Frame's last byte
  EXPECT_THROW(decode_frame(bytes), WireError);
}

// A Result of one 2x2 item of view 0 whose pixels are `payload` (a put_pixels payload
// without its count), claimed to be in encoding `e`.
std::vector<uint8_t> result_with_payload(ResultEncoding e, const std::vector<uint8_t>& payload,
                                         Rect rect = Rect{0, 0, 2, 2}) {
  ByteWriter w;
  w.put(uint32_t(1)), w.put(uint8_t(e)), w.put(uint64_t(1));
  w.put(uint32_t(0));
  w.put(int32_t(rect.x0)), w.put(int32_t(rect.y0)), w.put(int32_t(rect.x1)),
      w.put(int32_t(rect.y1)), w.put(int32_t(0));
  w.put(1.0), w.put(1.0), w.put(4.0), w.put(uint64_t(4));
  w.put(uint64_t(payload.size()));
  w.put_bytes(payload.data(), payload.size());
  w.put(uint8_t(0));               // no feature buffers
  w.put(uint64_t(0)), w.put(0.0);  // no local times, no idle time
  return w.take();
}

std::vector<uint8_t> payload_of(const std::vector<Vec3>& px, ResultEncoding e) {
  ByteWriter w;
  put_pixels(w, px, e);
  std::vector<uint8_t> bytes = w.take();
  return std::vector<uint8_t>(bytes.begin() + 8, bytes.end());
}

TEST(ResultEncoding, HostileResultsAreRefused) {
  const ResultBounds frame{16, 16, 1};
  // The message itself, well formed, is accepted.
  EXPECT_NO_THROW(
      decode_result(result_with_payload(ResultEncoding::float32,
                                        payload_of(sample_pixels(4), ResultEncoding::float32)),
                    frame));
  // An unknown encoding; raw pixels of the wrong count.
  EXPECT_THROW(decode_result(result_with_payload(ResultEncoding(9), {}), frame), WireError);
  EXPECT_THROW(
      decode_result(result_with_payload(ResultEncoding::half,
                                        payload_of(sample_pixels(5), ResultEncoding::half)),
                    frame),
      WireError);
  // An item outside the frame, or more pixels than the frame has.
  EXPECT_THROW(
      decode_result(result_with_payload(ResultEncoding::float32, {}, Rect{0, 0, 17, 1}), frame),
      WireError);
  EXPECT_THROW(decode_result(result_with_payload(ResultEncoding::float32, {}, Rect{0, 0, 2, 2}),
                             ResultBounds{2, 1, 1}),
               WireError);
  if (!zstd_available()) GTEST_SKIP() << "built without zstd";
  for (ResultEncoding e : {ResultEncoding::float_zstd, ResultEncoding::half_zstd}) {
    // A zstd frame of 5 pixels for a 2x2 rect: the sizes disagree.
    EXPECT_THROW(decode_result(result_with_payload(e, payload_of(sample_pixels(5), e)), frame),
                 WireError);
    // Garbage, a truncated frame, and bytes after the frame.
    const std::vector<uint8_t> good = payload_of(sample_pixels(4), e);
    EXPECT_NO_THROW(decode_result(result_with_payload(e, good), frame));
    EXPECT_THROW(decode_result(result_with_payload(e, {1, 2, 3, 4, 5, 6}), frame), WireError);
    for (size_t n = 0; n < good.size(); ++n)
      EXPECT_THROW(decode_result(result_with_payload(e, std::vector<uint8_t>(
                                                            good.begin(), good.begin() + long(n))),
                                 frame),
                   WireError)
          << n;
    std::vector<uint8_t> longer = good;
    longer.push_back(0);
    EXPECT_THROW(decode_result(result_with_payload(e, longer), frame), WireError);
    // A zstd frame header that claims 2^50 bytes (one empty last block follows): refused
    // from its header, before anything is allocated.
    std::vector<uint8_t> huge = {0x28, 0xb5, 0x2f, 0xfd,
                                 0xe0};  // magic; single segment, 8-byte size
    for (int b = 0; b < 8; ++b) huge.push_back(uint8_t((uint64_t(1) << 50) >> (8 * b)));
    huge.insert(huge.end(), {0x01, 0x00, 0x00});  // last block, raw, 0 bytes
    EXPECT_THROW(decode_result(result_with_payload(e, huge), frame), WireError);
  }
}

// The emulated link charges a result as it travels: compressed, its compressed bytes.
TEST(ResultEncoding, TheLinkChargesTheCompressedBytes) {
  if (!zstd_available()) GTEST_SKIP() << "built without zstd";
  ResultMessage m;
  ItemResult it;
  it.report.item = WorkItem{Rect{0, 0, 64, 64}, 0};
  it.pixels.assign(64 * 64, Vec3{0.25f, 0.5f, 0.75f});  // flat: compresses very well
  m.items = {it};
  const size_t raw = encode(m).size();
  m.encoding = ResultEncoding::float_zstd;
  const size_t packed = encode(m).size();
  EXPECT_GT(raw, 64u * 64 * 12);
  EXPECT_LT(packed * 20, raw);
  // 8 Mbit/s: one byte per microsecond, no latency.
  using Clock = LinkModel::Clock;
  LinkModel link(LinkSpec{"test", 0, 8, true}, 1);
  const Clock::time_point t0{};
  EXPECT_EQ(link.deliver_at(0, packed, t0), t0 + std::chrono::microseconds(packed));
}

}  // namespace result_encoding_test
}  // namespace multiray::remote
