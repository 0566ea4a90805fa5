// The viewer's WebSocket frame decoder (src/app/viewer/ws_frames.h) as pure functions: header
// forms, the checks of RFC 6455 §5 made from the header alone, fragments reassembled, and
// what a decoder holds whatever arrives.
#include "app/viewer/ws_frames.h"

#include <gtest/gtest.h>

#include <string>

#include "ws_raw_client.h"

namespace multiray::app::viewer::ws {
namespace {

using testing::client_frame;

TEST(WsFrames, HeadersOfEveryLengthFormAreReadAndShortOnesWaitForMore) {
  for (const uint64_t n : {0ull, 125ull, 126ull, 65535ull, 65536ull, 600'000'000ull}) {
    const std::string f = client_frame(0x81, "", true, n);
    FrameHeader h;
    EXPECT_FALSE(parse_header(std::string_view(f).substr(0, f.size() - 1), h)) << n;
    ASSERT_TRUE(parse_header(f, h)) << n;
    EXPECT_EQ(h.length, n);
    EXPECT_EQ(h.size, f.size());
    EXPECT_TRUE(h.fin && h.masked);
    EXPECT_EQ(h.opcode, kText);
    EXPECT_EQ(h.mask[3], 4);
  }
  FrameHeader h;
  ASSERT_TRUE(parse_header(client_frame(0x71, "x", false), h));
  EXPECT_EQ(h.rsv, 7);
  EXPECT_FALSE(h.fin || h.masked);
}

TEST(WsFrames, TheHeaderAloneDecidesRefusals) {
  const auto code = [](const std::string& frame, long long open = -1) {
    FrameHeader h;
    EXPECT_TRUE(parse_header(frame, h));
    return check_header(h, open).code;
  };
  EXPECT_EQ(code(client_frame(0x81, "", true, 4096)), 0);
  EXPECT_EQ(code(client_frame(0x81, "", true, 4097)), kTooBig);
  EXPECT_EQ(code(client_frame(0x81, "", true, 1ull << 63)), kTooBig);
  EXPECT_EQ(code(client_frame(0x80, "", true, 97), 4000), kTooBig);
  EXPECT_EQ(code(client_frame(0x80, "", true, 96), 4000), 0);
  EXPECT_EQ(code(client_frame(0x81, "x", false)), kProtocolError);
  EXPECT_EQ(code(client_frame(0x89, "", true, 125)), 0);
  EXPECT_EQ(code(client_frame(0x89, "", true, 126)), kProtocolError);
  EXPECT_EQ(code(client_frame(0x0a, "")), kProtocolError);
  for (int op : {3, 4, 5, 6, 7, 0xb, 0xc, 0xd, 0xe, 0xf})
    EXPECT_EQ(code(client_frame(uint8_t(0x80 | op), "")), kProtocolError) << op;
  for (int rsv : {0x40, 0x20, 0x10}) EXPECT_EQ(code(client_frame(uint8_t(0x81 | rsv), "")), 1002);
  EXPECT_EQ(code(client_frame(0x80, "")), kProtocolError);     // nothing to continue
  EXPECT_EQ(code(client_frame(0x82, ""), 3), kProtocolError);  // a message inside one
  EXPECT_EQ(code(client_frame(0x89, ""), 3), 0);               // a ping inside one: fine
}

// Fed one byte at a time: the same events as fed whole.
TEST(WsFrames, FragmentsAndControlFramesDecodeTheSameInAnyChunks) {
  const std::string bytes = client_frame(0x01, "{\"a\"") + client_frame(0x8a, "pong") +
                            client_frame(0x80, ":1}") + client_frame(0x82, "\xff") +
                            client_frame(0x89, "") +
                            client_frame(0x88,
                                         "\x03\xe8"
                                         "bye");
  for (const size_t chunk : {size_t(1), size_t(3), bytes.size()}) {
    Decoder d;
    std::vector<Event> events;
    for (size_t at = 0; at < bytes.size(); at += chunk) {
      d.pending.append(bytes.substr(at, chunk));
      for (Event e; (e = next_event(d)).kind != Event::kNone;) events.push_back(e);
    }
    ASSERT_EQ(events.size(), 5u) << chunk;
    EXPECT_EQ(events[0].kind, Event::kPong);
    EXPECT_EQ(events[0].payload, "pong");
    EXPECT_EQ(events[1].kind, Event::kMessage);
    EXPECT_EQ(events[1].opcode, kText);
    EXPECT_EQ(events[1].payload, "{\"a\":1}");
    EXPECT_EQ(events[2].opcode, kBinary);
    EXPECT_EQ(events[3].kind, Event::kPing);
    EXPECT_EQ(events[4].kind, Event::kClose);
    EXPECT_EQ(events[4].payload,
              "\x03\xe8"
              "bye");
    EXPECT_TRUE(d.done);
  }
}

// A refusal comes as soon as the header is complete, and ends the decoder.
TEST(WsFrames, ARefusalEndsTheDecoderBeforeThePayload) {
  Decoder d;
  d.pending = client_frame(0x81, "", true, 600'000'000);
  Event e = next_event(d);
  EXPECT_EQ(e.kind, Event::kRefuse);
  EXPECT_EQ(e.refusal.code, kTooBig);
  EXPECT_TRUE(d.done && d.pending.empty());
  d.pending = client_frame(0x81, "{}");
  EXPECT_EQ(next_event(d).kind, Event::kNone);
}

TEST(WsFrames, CloseBodiesAndTextAreChecked) {
  const auto refusal = [](const std::string& frame) {
    Decoder d;
    d.pending = frame;
    const Event e = next_event(d);
    return e.kind == Event::kRefuse ? e.refusal.code : 0;
  };
  EXPECT_EQ(refusal(client_frame(0x88, "")), 0);
  EXPECT_EQ(refusal(client_frame(0x88, "\x03")), kProtocolError);
  EXPECT_EQ(refusal(client_frame(0x88, std::string("\x03\xed", 2))), kProtocolError);  // 1005
  EXPECT_EQ(refusal(client_frame(0x88, "\x03\xe8\xff")), kInvalidData);
  EXPECT_EQ(refusal(client_frame(0x81, "\xed\xa0\x80")), kInvalidData);  // a surrogate
  EXPECT_EQ(refusal(client_frame(0x82, "\xed\xa0\x80")), 0);             // binary: not text
}

TEST(WsFrames, Utf8) {
  EXPECT_TRUE(valid_utf8(""));
  EXPECT_TRUE(valid_utf8("plain {\"json\"}"));
  EXPECT_TRUE(valid_utf8("\xc3\xa9\xe2\x82\xac\xf0\x9f\x98\x80"));  // é € 😀
  EXPECT_TRUE(valid_utf8("\xf4\x8f\xbf\xbf"));                      // U+10FFFF
  EXPECT_FALSE(valid_utf8("\xc0\xaf"));                             // overlong '/'
  EXPECT_FALSE(valid_utf8("\xe0\x80\xaf"));
  EXPECT_FALSE(valid_utf8("\xf4\x90\x80\x80"));  // beyond U+10FFFF
  EXPECT_FALSE(valid_utf8("\xed\xbf\xbf"));      // a surrogate
  EXPECT_FALSE(valid_utf8("\xe2\x82"));          // cut short
  EXPECT_FALSE(valid_utf8("\x80"));
  EXPECT_FALSE(valid_utf8("\xff"));
}

TEST(WsFrames, CloseBodyIsTheCodeThenTheReasonCutTo123Bytes) {
  const std::string b = close_body(kTooBig, std::string(200, 'r'));
  ASSERT_EQ(b.size(), 125u);
  EXPECT_EQ(uint8_t(b[0]) << 8 | uint8_t(b[1]), 1009);
}

}  // namespace
}  // namespace multiray::app::viewer::ws
