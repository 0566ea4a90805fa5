// A result's pixels on the wire, in one of the --result-encoding forms
// (util/result_encoding.h): 32-bit floats, 16-bit half floats, and either compressed with
// zstd after its bytes are split into planes (every value's first byte, then every
// value's second, ...: the exponent bytes of neighbouring pixels are alike, which zstd
// finds). Each pixel is encoded on its own, so a frame's pixels do not depend on how it
// was split; the lossless encodings give back the very floats that were sent.
#pragma once

#include <cstdint>
#include <vector>

#include "core/math.h"
#include "distributed/wire.h"
#include "util/result_encoding.h"

namespace multiray::remote {

// Whether this build has zstd (MULTIRAY_WITH_ZSTD): without it the zstd encodings are
// refused (check_result_encoding) and never decoded.
bool zstd_available();
// Throws std::invalid_argument for an encoding this build cannot send.
void check_result_encoding(ResultEncoding e);

// The half float nearest to `v` (ties to even; subnormal halves kept), as its bits, and
// back. Finite values beyond the largest half (65504) become it, with their sign, rather
// than infinity; infinities stay infinite and NaN stays NaN.
uint16_t half_bits(float v);
float half_value(uint16_t bits);
// half_value(half_bits(v)): what a lossy encoding makes of `v`.
inline float round_to_half(float v) { return half_value(half_bits(v)); }

// Appends v[0..n) as `e`: the payload's byte count, then the payload. (Feature buffers
// travel so, core/feature_buffers.h's packed floats; the beauty through put_pixels.)
void put_values(ByteWriter& w, const float* v, size_t n, ResultEncoding e);
// Reads `count` floats written by put_values with `e` into v[0..count), with get_pixels'
// checks.
void get_values(ByteReader& r, ResultEncoding e, size_t count, float* v);

// Appends `pixels` as `e`: the payload's byte count, then the payload.
void put_pixels(ByteWriter& w, const std::vector<Vec3>& pixels, ResultEncoding e);
// Reads `count` pixels written by put_pixels with `e`. Throws WireError for a payload that
// does not hold exactly `count` pixels; a compressed one must say so in its header before
// anything is decompressed, so no message makes this allocate more than `count` pixels.
std::vector<Vec3> get_pixels(ByteReader& r, ResultEncoding e, size_t count);

}  // namespace multiray::remote
