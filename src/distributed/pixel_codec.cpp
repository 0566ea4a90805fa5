#include "distributed/pixel_codec.h"

#include <Imath/half.h>  // Imath's half (with OpenEXR, already a dependency of multiray_core)

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>

#ifdef MULTIRAY_HAS_ZSTD
#include <zstd.h>
#endif

namespace multiray::remote {

namespace {

// zstd's fastest level: results are compressed on the worker's render thread, and level 1
// keeps that well under the time the bytes would take on a thin link.
constexpr int kZstdLevel = 1;

// `n` floats as they travel before compression: 4 bytes or a half's 2 each.
std::vector<uint8_t> raw_values(const float* v, size_t n, bool half) {
  std::vector<uint8_t> out(n * (half ? 2 : 4));
  if (!half) {
    if (n) std::memcpy(out.data(), v, out.size());
    return out;
  }
  for (size_t i = 0; i < n; ++i) {
    const uint16_t h = half_bits(v[i]);
    std::memcpy(out.data() + 2 * i, &h, 2);
  }
  return out;
}

// `count` floats from raw_values' bytes into `v`.
void from_values(const uint8_t* bytes, size_t count, bool half, float* v) {
  if (!half) {
    if (count) std::memcpy(v, bytes, count * 4);
    return;
  }
  for (size_t i = 0; i < count; ++i) {
    uint16_t h;
    std::memcpy(&h, bytes + 2 * i, 2);
    v[i] = half_value(h);
  }
}

// `bytes` read as a rows x cols matrix, transposed. Values of `size` bytes become byte
// planes (plane b: byte b of every value) with rows = count, cols = size; back with the two
// swapped.
std::vector<uint8_t> transpose(const std::vector<uint8_t>& bytes, size_t rows, size_t cols) {
  std::vector<uint8_t> out(bytes.size());
  for (size_t r = 0; r < rows; ++r)
    for (size_t c = 0; c < cols; ++c) out[c * rows + r] = bytes[r * cols + c];
  return out;
}

#ifdef MULTIRAY_HAS_ZSTD
std::vector<uint8_t> compress(const std::vector<uint8_t>& raw) {
  thread_local std::unique_ptr<ZSTD_CCtx, size_t (*)(ZSTD_CCtx*)> ctx(ZSTD_createCCtx(),
                                                                      ZSTD_freeCCtx);
  std::vector<uint8_t> out(ZSTD_compressBound(raw.size()));
  const size_t n =
      ZSTD_compressCCtx(ctx.get(), out.data(), out.size(), raw.data(), raw.size(), kZstdLevel);
  if (ZSTD_isError(n))
    throw std::runtime_error(std::string("zstd could not compress a result: ") +
                             ZSTD_getErrorName(n));
  out.resize(n);
  return out;
}

// Exactly `expected` bytes from one zstd frame that must declare that size in its header:
// checked before anything is allocated or decompressed.
std::vector<uint8_t> decompress(const uint8_t* p, size_t n, size_t expected) {
  const unsigned long long declared = ZSTD_getFrameContentSize(p, n);
  if (declared == ZSTD_CONTENTSIZE_ERROR || declared == ZSTD_CONTENTSIZE_UNKNOWN)
    throw WireError("result pixels: not a zstd frame that states its size");
  if (declared != expected)
    throw WireError("result pixels: the zstd frame holds " + std::to_string(declared) +
                    " bytes, the item's rect " + std::to_string(expected));
  if (ZSTD_findFrameCompressedSize(p, n) != n)
    throw WireError("result pixels: bytes after the zstd frame");
  thread_local std::unique_ptr<ZSTD_DCtx, size_t (*)(ZSTD_DCtx*)> ctx(ZSTD_createDCtx(),
                                                                      ZSTD_freeDCtx);
  std::vector<uint8_t> out(static_cast<size_t>(declared));  // the rect's size (checked)
  const size_t got = ZSTD_decompressDCtx(ctx.get(), out.data(), out.size(), p, n);
  if (ZSTD_isError(got) || got != expected)
    throw WireError("result pixels: the zstd frame does not decompress");
  return out;
}
#endif

}  // namespace

bool zstd_available() {
#ifdef MULTIRAY_HAS_ZSTD
  return true;
#else
  return false;
#endif
}

void check_result_encoding(ResultEncoding e) {
  if (uses_zstd(e) && !zstd_available())
    throw std::invalid_argument("'" + result_encoding_name(e) +
                                "' needs zstd, and this multiray was built without it "
                                "(install libzstd-dev and configure again)");
}

uint16_t half_bits(float v) {
  // Imath rounds to the nearest half, ties to even, and keeps subnormals, infinities and
  // NaN; finite floats past the largest half would become infinity there.
  if (std::isfinite(v)) v = std::clamp(v, -65504.0f, 65504.0f);
  return Imath::half(v).bits();
}

float half_value(uint16_t bits) {
  Imath::half h;
  h.setBits(bits);
  return float(h);
}

void put_values(ByteWriter& w, const float* v, size_t n, ResultEncoding e) {
  check_result_encoding(e);
  const bool half = is_lossy(e);
  std::vector<uint8_t> payload = raw_values(v, n, half);
#ifdef MULTIRAY_HAS_ZSTD
  if (uses_zstd(e))
    payload = compress(transpose(payload, payload.size() / (half ? 2 : 4), half ? 2 : 4));
#endif
  w.put(uint64_t(payload.size()));
  w.put_bytes(payload.data(), payload.size());
}

void get_values(ByteReader& r, ResultEncoding e, size_t count, float* v) {
  const bool half = is_lossy(e);
  const size_t expected = count * (half ? 2 : 4);
  const size_t n = size_t(r.count(1));
  const uint8_t* payload = r.get_bytes(n);
  if (!uses_zstd(e)) {
    if (n != expected) throw WireError("result pixels do not match the item's rect");
    return from_values(payload, count, half, v);
  }
#ifdef MULTIRAY_HAS_ZSTD
  const std::vector<uint8_t> planes = decompress(payload, n, expected);
  from_values(transpose(planes, half ? 2 : 4, planes.size() / (half ? 2 : 4)).data(), count, half,
              v);
#else
  throw WireError("result pixels compressed with zstd, and this multiray has no zstd");
#endif
}

void put_pixels(ByteWriter& w, const std::vector<Vec3>& pixels, ResultEncoding e) {
  put_values(w, pixels.empty() ? nullptr : &pixels.data()->x, pixels.size() * 3, e);
}

std::vector<Vec3> get_pixels(ByteReader& r, ResultEncoding e, size_t count) {
  std::vector<Vec3> out(count);
  get_values(r, e, count * 3, count ? &out.data()->x : nullptr);
  return out;
}

}  // namespace multiray::remote
