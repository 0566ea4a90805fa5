// How a worker's pixels travel back to the master (--result-encoding), shared by
// `render --distributed` (distributed/pixel_codec.h encodes them) and `simulate` (which
// charges the link the bytes they would take). Standard library only.
#pragma once

#include <cstdint>
#include <string>

namespace multiray {

// The wire value of each encoding is its enumerator (one byte in a Frame and a Result).
enum class ResultEncoding : uint8_t {
  float32 = 0,     // three 32-bit floats per pixel (12 bytes), exact
  half = 1,        // three 16-bit half floats (6 bytes): lossy, about 3 significant digits
  float_zstd = 2,  // float32, byte planes compressed with zstd: exact
  half_zstd = 3,   // half, byte planes compressed with zstd: lossy as half
};
inline constexpr int kResultEncodings = 4;

// "float", "half", "float+zstd" or "half+zstd".
std::string result_encoding_name(ResultEncoding e);
// The inverse of result_encoding_name; throws std::invalid_argument "'TEXT': must be ...".
ResultEncoding parse_result_encoding(const std::string& text);

inline bool is_lossy(ResultEncoding e) {
  return e == ResultEncoding::half || e == ResultEncoding::half_zstd;
}
inline bool uses_zstd(ResultEncoding e) {
  return e == ResultEncoding::float_zstd || e == ResultEncoding::half_zstd;
}
// Bytes per pixel before compression: 12 (float) or 6 (half).
inline int raw_bytes_per_pixel(ResultEncoding e) { return is_lossy(e) ? 6 : 12; }

// Compressed size / size before compression of the zstd encodings, measured on one frame
// of Sponza (640x360, 1 spp, docs/distributed.md "Result encodings"); 1 for the others.
// The simulator's default; real frames compress differently (noise compresses worse).
double measured_zstd_ratio(ResultEncoding e);

// What the simulator charges per pixel: raw_bytes_per_pixel x `ratio` for the zstd
// encodings (ratio in (0, 1]; the measured one when negative), raw otherwise.
double result_bytes_per_pixel(ResultEncoding e, double ratio = -1);

}  // namespace multiray
