// The viewer's reading of WebSocket frames from a client (RFC 6455 §5), as pure functions
// over bytes: civetweb reads a whole frame into memory before its data handler sees it (a
// declared 600 MB frame is allocated and read), so the server takes the connection over after
// civetweb's handshake and decodes what arrives here. Limits act on the frame header, before
// any payload is read: a frame or message declaring more than kMaxMessageBytes, or a control
// frame more than kMaxControlBytes, is refused as soon as its header is complete.
//
// A decoder holds at most one frame's header and payload plus one message being assembled:
// under 2 * kMaxMessageBytes + 14 bytes per connection, whatever the client sends.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace multiray::app::viewer::ws {

constexpr size_t kMaxMessageBytes = 4096;  // a data frame or an assembled message
constexpr size_t kMaxControlBytes = 125;   // ping, pong, close (§5.5)

enum Opcode : uint8_t {
  kContinuation = 0x0,
  kText = 0x1,
  kBinary = 0x2,
  kClose = 0x8,
  kPing = 0x9,
  kPong = 0xa,
};

// Close codes the server sends (§7.4.1).
enum CloseCode : uint16_t {
  kNormalClosure = 1000,
  kProtocolError = 1002,
  kInvalidData = 1007,  // a text message that is not UTF-8
  kTooBig = 1009,
};

struct FrameHeader {
  bool fin = false;
  uint8_t rsv = 0;  // RSV1-3 as the 3 bits 0x4, 0x2, 0x1
  uint8_t opcode = 0;
  bool masked = false;
  uint64_t length = 0;  // payload bytes declared
  uint8_t mask[4] = {0, 0, 0, 0};
  size_t size = 0;  // header bytes: 2..14
};

// Reads the header at the start of `bytes` into `h`: false while fewer bytes than the header
// needs have arrived (at most 14 are ever needed). Any declared length is read as declared.
bool parse_header(std::string_view bytes, FrameHeader& h);

// What is wrong with a client's frame `h` under RFC 6455, as a close code (0: nothing) and a
// reason; `open_message`: the bytes of a fragmented message assembled so far, or -1 when none
// is open. Needs nothing but the header, so it runs before the payload is read.
struct Refusal {
  uint16_t code = 0;
  std::string reason;
};
Refusal check_header(const FrameHeader& h, long long open_message);

// One connection's incoming state: plain data, advanced by next_event().
struct Decoder {
  std::string pending;         // bytes received and not yet decoded: at most one frame
  std::string message;         // the fragments of the open message
  uint8_t message_opcode = 0;  // kText or kBinary while a fragmented message is open, else 0
  bool done = false;           // a close or a refusal was returned: nothing more is decoded
};

struct Event {
  enum Kind { kNone, kMessage, kPing, kPong, kClose, kRefuse };
  Kind kind = kNone;    // kNone: more bytes are needed (or the decoder is done)
  uint8_t opcode = 0;   // kMessage: kText or kBinary
  std::string payload;  // the message, the ping's or pong's data, or the close frame's body
  Refusal refusal;      // kRefuse: why, and the close code to send
};

// Takes the next whole message or control frame out of `d.pending` (consuming its bytes),
// unmasked. A refusal ends the decoder: the caller sends refusal.code in a close frame and
// closes the connection. Bytes beyond the one frame being read are never buffered by the
// caller: it appends at most kReadBytes at a time and calls this until kNone.
Event next_event(Decoder& d);
constexpr size_t kReadBytes = 4096;

// Whether `s` is well-formed UTF-8 (no overlong forms, surrogates or code points > U+10FFFF).
bool valid_utf8(std::string_view s);

// A close frame's body: the code, big-endian, then the reason cut to 123 bytes (§5.5.1).
std::string close_body(uint16_t code, std::string_view reason);

}  // namespace multiray::app::viewer::ws
