#include "app/viewer/ws_frames.h"

namespace multiray::app::viewer::ws {

namespace {
bool is_control(uint8_t opcode) { return opcode >= 0x8; }

// Close codes a peer may send (§7.4.1, §7.4.2): 1000-1003, 1007-1014, 3000-4999.
bool valid_close_code(unsigned code) {
  return (code >= 1000 && code <= 1003) || (code >= 1007 && code <= 1014) ||
         (code >= 3000 && code <= 4999);
}

Event refuse(Decoder& d, uint16_t code, std::string reason) {
  d.done = true;
  d.pending.clear();
  d.message.clear();
  Event e;
  e.kind = Event::kRefuse;
  e.refusal = {code, std::move(reason)};
  return e;
}

// The close frame's body `body` checked (§5.5.1, §7.1.6): empty, or a valid code and UTF-8.
Refusal check_close_body(std::string_view body) {
  if (body.empty()) return {};
  if (body.size() == 1) return {kProtocolError, "a close frame with a 1-byte body"};
  const unsigned code = unsigned(uint8_t(body[0])) << 8 | uint8_t(body[1]);
  if (!valid_close_code(code))
    return {kProtocolError, "close code " + std::to_string(code) + " is not one a peer may send"};
  if (!valid_utf8(body.substr(2))) return {kInvalidData, "a close reason that is not UTF-8"};
  return {};
}
}  // namespace

bool parse_header(std::string_view bytes, FrameHeader& h) {
  if (bytes.size() < 2) return false;
  const auto* b = reinterpret_cast<const uint8_t*>(bytes.data());
  h.fin = (b[0] & 0x80) != 0;
  h.rsv = (b[0] >> 4) & 0x7;
  h.opcode = b[0] & 0xf;
  h.masked = (b[1] & 0x80) != 0;
  const uint8_t len7 = b[1] & 0x7f;
  const size_t extra = len7 == 126 ? 2 : len7 == 127 ? 8 : 0;
  h.size = 2 + extra + (h.masked ? 4 : 0);
  if (bytes.size() < h.size) return false;
  h.length = len7;
  if (extra > 0) {
    h.length = 0;
    for (size_t i = 0; i < extra; ++i) h.length = h.length << 8 | b[2 + i];
  }
  for (int i = 0; i < 4; ++i) h.mask[i] = h.masked ? b[2 + extra + i] : 0;
  return true;
}

Refusal check_header(const FrameHeader& h, long long open_message) {
  if (h.rsv != 0) return {kProtocolError, "RSV bits set without a negotiated extension"};
  if ((h.opcode >= 0x3 && h.opcode <= 0x7) || h.opcode >= 0xb)
    return {kProtocolError, "reserved opcode " + std::to_string(h.opcode)};
  if (!h.masked) return {kProtocolError, "a client frame that is not masked"};
  if (is_control(h.opcode)) {
    if (!h.fin) return {kProtocolError, "a fragmented control frame"};
    if (h.length > kMaxControlBytes) return {kProtocolError, "a control frame over 125 bytes"};
    return {};
  }
  if (h.opcode == kContinuation && open_message < 0)
    return {kProtocolError, "a continuation frame with no message to continue"};
  if (h.opcode != kContinuation && open_message >= 0)
    return {kProtocolError, "a new message inside a fragmented one"};
  const uint64_t so_far = open_message < 0 ? 0 : uint64_t(open_message);
  if (h.length > kMaxMessageBytes || so_far + h.length > kMaxMessageBytes)
    return {kTooBig, "message longer than " + std::to_string(kMaxMessageBytes) + " bytes"};
  return {};
}

Event next_event(Decoder& d) {
  for (;;) {
    FrameHeader h;
    if (d.done || !parse_header(d.pending, h)) return {};
    const long long open = d.message_opcode ? (long long)d.message.size() : -1;
    if (Refusal r = check_header(h, open); r.code != 0) return refuse(d, r.code, r.reason);
    // The checks bound h.length by kMaxMessageBytes: the whole frame fits in memory.
    const size_t total = h.size + size_t(h.length);
    if (d.pending.size() < total) return {};
    std::string payload = d.pending.substr(h.size, size_t(h.length));
    d.pending.erase(0, total);
    for (size_t i = 0; i < payload.size(); ++i) payload[i] = char(payload[i] ^ h.mask[i & 3]);

    Event e;
    e.payload = std::move(payload);
    switch (h.opcode) {
      case kPing:
        e.kind = Event::kPing;
        return e;
      case kPong:
        e.kind = Event::kPong;
        return e;
      case kClose:
        if (Refusal r = check_close_body(e.payload); r.code != 0)
          return refuse(d, r.code, r.reason);
        d.done = true;
        e.kind = Event::kClose;
        return e;
      default:
        break;
    }
    if (h.opcode != kContinuation) d.message_opcode = h.opcode;
    d.message += e.payload;
    if (!h.fin) continue;  // the next fragment, or the bytes for it
    e.kind = Event::kMessage;
    e.opcode = d.message_opcode;
    e.payload = std::move(d.message);
    d.message.clear();
    d.message_opcode = 0;
    if (e.opcode == kText && !valid_utf8(e.payload))
      return refuse(d, kInvalidData, "a text message that is not UTF-8");
    return e;
  }
}

bool valid_utf8(std::string_view s) {
  const auto* p = reinterpret_cast<const uint8_t*>(s.data());
  const size_t n = s.size();
  for (size_t i = 0; i < n;) {
    const uint8_t c = p[i];
    if (c < 0x80) {
      ++i;
      continue;
    }
    size_t len = 0;
    uint32_t cp = 0, min = 0;
    if ((c & 0xe0) == 0xc0)
      len = 2, cp = c & 0x1f, min = 0x80;
    else if ((c & 0xf0) == 0xe0)
      len = 3, cp = c & 0x0f, min = 0x800;
    else if ((c & 0xf8) == 0xf0)
      len = 4, cp = c & 0x07, min = 0x10000;
    else
      return false;
    if (i + len > n) return false;
    for (size_t k = 1; k < len; ++k) {
      if ((p[i + k] & 0xc0) != 0x80) return false;
      cp = cp << 6 | (p[i + k] & 0x3f);
    }
    if (cp < min || cp > 0x10ffff || (cp >= 0xd800 && cp <= 0xdfff)) return false;
    i += len;
  }
  return true;
}

std::string close_body(uint16_t code, std::string_view reason) {
  std::string body;
  body += char(code >> 8);
  body += char(code & 0xff);
  body += reason.substr(0, kMaxControlBytes - 2);
  return body;
}

}  // namespace multiray::app::viewer::ws
