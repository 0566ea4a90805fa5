// The viewer's web server read by a client that writes raw WebSocket frames (issue 53, item
// 5). Before, civetweb read each whole frame into memory before any limit applied (three
// clients declaring 600 MB frames took the process to 1.7 GB), passed each fragment on as a
// message ("not a JSON object"), and took unmasked frames, 200-byte pings, reserved opcodes
// and RSV bits.
#include <civetweb.h>
#include <gtest/gtest.h>

#include <chrono>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "app/viewer/web_server.h"
#include "raw_socket.h"
#include "ws_raw_client.h"

namespace multiray::app::viewer {
namespace ws_protocol_test {

using namespace std::chrono_literals;
using testing::client_frame;
using testing::close_code;
using testing::kHandshake;
using testing::server_frames;
using testing::Socket;

// A server on a free loopback port (no greeting) that keeps the messages it is given.
struct Server {
  std::mutex mutex;
  std::vector<std::string> messages;
  std::unique_ptr<WebServer> server;
  Server() {
    mg_init_library(MG_FEATURES_WEBSOCKET);
    server = std::make_unique<WebServer>(parse_listen_address("127.0.0.1", false), 0, 4,
                                         "<p>viewer</p>", nullptr,
                                         [this](int, const std::string& text) {
                                           std::lock_guard<std::mutex> lock(mutex);
                                           messages.push_back(text);
                                         });
  }
  std::vector<std::string> got() {
    std::lock_guard<std::mutex> lock(mutex);
    return messages;
  }
};

// A socket past the handshake (its 101 answer read).
std::unique_ptr<Socket> upgraded(int port) {
  auto s = std::make_unique<Socket>(port);
  EXPECT_TRUE(s->ok() && s->send(kHandshake));
  const std::string reply =
      s->read(10s, [](const std::string& r) { return r.find("\r\n\r\n") != std::string::npos; });
  EXPECT_EQ(reply.rfind("HTTP/1.1 101", 0), 0u) << reply;
  return s;
}

// Sends `bytes` after the handshake; returns the close code the server answered with (0: no
// close frame) and whether it then closed the connection, within 10 s.
std::pair<int, bool> answer_to(int port, const std::string& bytes) {
  auto s = upgraded(port);
  EXPECT_TRUE(s->send(bytes));
  const std::string got = s->read(10s);
  return {close_code(server_frames(got)), s->closed_by_peer()};
}

// Only the 14 header bytes of a text frame declaring 600 MB are sent: the server answers
// 1009 (message too big) and closes without waiting for a payload byte, so none is held.
TEST(WebSocketProtocol, AFrameDeclaringMoreThanTheLimitIsRefusedFromItsHeader) {
  Server s;
  const std::string header = client_frame(0x81, "", true, 600'000'000);
  ASSERT_EQ(header.size(), 14u);
  const auto [code, closed] = answer_to(s.server->port(), header);
  EXPECT_EQ(code, 1009);
  EXPECT_TRUE(closed);
  // Declared in the 16-bit form: 5000 bytes, over 4096.
  EXPECT_EQ(answer_to(s.server->port(), client_frame(0x81, "", true, 5000)).first, 1009);
  EXPECT_TRUE(s.got().empty());
}

// A JSON message in three fragments with a ping between them: one message, whole, and the
// ping answered with a pong carrying its data.
TEST(WebSocketProtocol, AFragmentedMessageArrivesWhole) {
  Server s;
  auto sock = upgraded(s.server->port());
  const std::string json = R"({"type":"zoom","factor":2})";
  ASSERT_TRUE(sock->send(client_frame(0x01, json.substr(0, 9)) + client_frame(0x89, "hi") +
                         client_frame(0x00, json.substr(9, 8)) +
                         client_frame(0x80, json.substr(17))));
  const std::string got =
      sock->read(10s, [](const std::string& r) { return !server_frames(r).empty(); });
  const auto frames = server_frames(got);
  ASSERT_EQ(frames.size(), 1u) << got;
  EXPECT_EQ(frames[0].opcode, 0xa);
  EXPECT_EQ(frames[0].payload, "hi");
  for (int i = 0; i < 1000 && s.got().empty(); ++i) std::this_thread::sleep_for(10ms);
  EXPECT_EQ(s.got(), std::vector<std::string>{json});
  // A close from the client is answered with its code, and the connection ends.
  ASSERT_TRUE(sock->send(client_frame(0x88, std::string("\x03\xe8", 2))));
  EXPECT_EQ(close_code(server_frames(sock->read(10s))), 1000);
  EXPECT_TRUE(sock->closed_by_peer());
}

// Each violation of RFC 6455 §5 closes its connection with its code; none is a message.
TEST(WebSocketProtocol, ProtocolViolationsCloseWithTheirCode) {
  Server s;
  const std::string json = R"({"type":"reset"})";
  const struct {
    const char* what;
    std::string bytes;
    int code;
  } cases[] = {
      {"an unmasked text frame", client_frame(0x81, json, false), 1002},
      {"a 200-byte ping", client_frame(0x89, std::string(200, 'p')), 1002},
      {"a fragmented ping", client_frame(0x09, "p"), 1002},
      {"reserved opcode 3", client_frame(0x83, json), 1002},
      {"reserved opcode 0xB", client_frame(0x8b, ""), 1002},
      {"RSV1 set", client_frame(0xc1, json), 1002},
      {"RSV3 set", client_frame(0x91, json), 1002},
      {"a continuation with nothing to continue", client_frame(0x80, json), 1002},
      {"a new message inside a fragmented one", client_frame(0x01, "{") + client_frame(0x81, json),
       1002},
      {"fragments adding up to more than 4096 bytes",
       client_frame(0x01, std::string(4000, ' ')) + client_frame(0x80, std::string(200, ' ')),
       1009},
      {"text that is not UTF-8", client_frame(0x81, "{\"type\":\"\xc0\xaf\"}"), 1007},
  };
  for (const auto& c : cases) {
    const auto [code, closed] = answer_to(s.server->port(), c.bytes);
    EXPECT_EQ(code, c.code) << c.what;
    EXPECT_TRUE(closed) << c.what;
  }
  EXPECT_TRUE(s.got().empty()) << s.got().front();
}

}  // namespace ws_protocol_test
}  // namespace multiray::app::viewer
