// PNG files built in memory for tests, without an encoder library: 8-bit grey, the image
// data in stored (uncompressed) deflate blocks. `png_bytes(w, h)` is a valid w x h image;
// `png_claiming(w, h)` has the header of a w x h image but the data of one row, the way
// a tiny hostile file claims a huge image (stb_image reads the size from the header; the
// decode itself would fail).
#pragma once

#include <cstdint>
#include <string>

namespace multiray::test {

inline uint32_t png_crc(const std::string& bytes) {
  uint32_t c = 0xffffffffu;
  for (unsigned char b : bytes) {
    c ^= b;
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
  }
  return c ^ 0xffffffffu;
}

inline std::string png_be32(uint32_t v) {
  return {char(v >> 24), char(v >> 16), char(v >> 8), char(v)};
}

// One chunk: length, type, data, CRC of type and data.
inline std::string png_chunk(const std::string& type, const std::string& data) {
  return png_be32(uint32_t(data.size())) + type + data + png_be32(png_crc(type + data));
}

// A grey PNG whose header says width x height and whose data hold `rows` rows of
// mid-grey (each a filter byte 0 and `width` bytes), at most 65535 bytes of data.
inline std::string png_with_rows(uint32_t width, uint32_t height, uint32_t rows) {
  std::string raw;
  for (uint32_t y = 0; y < rows; ++y) raw += '\0' + std::string(width, '\x80');
  uint32_t a = 1, b = 0;  // Adler-32 of the raw data
  for (unsigned char c : raw) a = (a + c) % 65521, b = (b + a) % 65521;
  const uint16_t len = uint16_t(raw.size());
  std::string zlib = "\x78\x01";  // deflate, 32K window, no preset dictionary
  zlib += '\x01';                 // one final stored block
  zlib += {char(len & 0xff), char(len >> 8), char(~len & 0xff), char((~len >> 8) & 0xff)};
  zlib += raw + png_be32((b << 16) | a);
  const std::string ihdr = png_be32(width) + png_be32(height) + std::string{8, 0, 0, 0, 0};
  return std::string("\x89PNG\r\n\x1a\n", 8) + png_chunk("IHDR", ihdr) + png_chunk("IDAT", zlib) +
         png_chunk("IEND", "");
}

inline std::string png_bytes(uint32_t width, uint32_t height) {
  return png_with_rows(width, height, height);
}
inline std::string png_claiming(uint32_t width, uint32_t height) {
  return png_with_rows(width, height, 1);
}

}  // namespace multiray::test
