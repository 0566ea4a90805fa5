// WebSocket frames as a client writes them, byte for byte (RFC 6455 §5.2), and the server's
// frames read back: for tests that send what a browser never would.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace multiray::testing {

// A client frame: `first` is the first byte (FIN, RSV, opcode), then the length, declared as
// `declared` (default: the payload's size) in the shortest form, the mask key 1 2 3 4 when
// `masked`, and `payload` masked with it.
inline std::string client_frame(uint8_t first, const std::string& payload, bool masked = true,
                                uint64_t declared = UINT64_MAX) {
  const uint64_t n = declared == UINT64_MAX ? payload.size() : declared;
  std::string f(1, char(first));
  const char m = masked ? char(0x80) : 0;
  if (n < 126) {
    f += char(m | char(n));
  } else if (n < 65536) {
    f += char(m | 126);
    f += char(n >> 8), f += char(n & 0xff);
  } else {
    f += char(m | 127);
    for (int i = 7; i >= 0; --i) f += char((n >> (8 * i)) & 0xff);
  }
  const char key[4] = {1, 2, 3, 4};
  if (masked) f.append(key, 4);
  for (size_t i = 0; i < payload.size(); ++i)
    f += masked ? char(payload[i] ^ key[i & 3]) : payload[i];
  return f;
}

struct ServerFrame {
  int opcode = 0;
  std::string payload;
};

// The whole server frames in `bytes` (unmasked, as a server sends them), in order.
inline std::vector<ServerFrame> server_frames(const std::string& bytes) {
  std::vector<ServerFrame> out;
  size_t at = 0;
  while (at + 2 <= bytes.size()) {
    const auto* b = reinterpret_cast<const uint8_t*>(bytes.data() + at);
    uint64_t n = b[1] & 0x7f;
    size_t head = 2;
    if (n == 126 || n == 127) {
      const size_t extra = n == 126 ? 2 : 8;
      if (at + 2 + extra > bytes.size()) break;
      n = 0;
      for (size_t i = 0; i < extra; ++i) n = n << 8 | b[2 + i];
      head += extra;
    }
    if (at + head + n > bytes.size()) break;
    out.push_back({b[0] & 0xf, bytes.substr(at + head, size_t(n))});
    at += head + size_t(n);
  }
  return out;
}

// The code of the first close frame in `frames`; 0 when there is none, -1 for an empty body.
inline int close_code(const std::vector<ServerFrame>& frames) {
  for (const ServerFrame& f : frames)
    if (f.opcode == 0x8)
      return f.payload.size() < 2 ? -1 : uint8_t(f.payload[0]) << 8 | uint8_t(f.payload[1]);
  return 0;
}

}  // namespace multiray::testing
