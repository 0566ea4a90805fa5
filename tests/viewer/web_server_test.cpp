// The viewer's web server in this process, its frames sent by the test: a client that never
// reads holds up nobody. Before issue 31 every send held one lock and blocked until the
// client read (or 30 s passed), so such a client froze every other one.
#include <civetweb.h>
#include <gtest/gtest.h>

#include <chrono>
#include <memory>
#include <string>
#include <thread>

#include "app/viewer/web_server.h"
#include "raw_socket.h"
#include "ws_client.h"

namespace multiray::app::viewer {
namespace web_server_test {

using namespace std::chrono_literals;
using testing::Client;
using testing::kHandshake;
using testing::Socket;

// Whether `pred` holds within 20 s.
bool soon(const std::function<bool()>& pred) {
  const auto until = std::chrono::steady_clock::now() + 20s;
  while (!pred()) {
    if (std::chrono::steady_clock::now() > until) return false;
    std::this_thread::sleep_for(10ms);
  }
  return true;
}

// 24 frames of 1 MB: the client that never reads takes in a few (its socket buffers, some
// 4 MB on Linux) and then none, yet the other client gets every one while the first is still
// connected (it is dropped only after its writes made no progress for 5 s), and the frames
// the first missed are counted as skipped.
TEST(WebServer, AClientThatNeverReadsDelaysNoOtherClient) {
  mg_init_library(MG_FEATURES_WEBSOCKET);
  WebServer server(
      parse_listen_address("127.0.0.1", false), 0, 4, "<p>viewer</p>",
      [] { return std::string(R"({"type":"hello"})"); }, nullptr);
  Socket stuck(server.port(), 4096);
  ASSERT_TRUE(stuck.ok() && stuck.send(kHandshake));
  ASSERT_TRUE(soon([&] { return server.clients() == 1; }));
  Client reader(server.port());
  ASSERT_TRUE(reader.connected()) << reader.error();
  ASSERT_FALSE(reader.wait_type("hello").is_null());
  const std::string jpeg = "\xff\xd8" + std::string(1 << 20, 'x');
  for (size_t i = 1; i <= 24; ++i) {
    server.broadcast_frame(std::make_shared<const OutFrame>(
        OutFrame{R"({"type":"frame","frame":)" + std::to_string(i) + "}", jpeg}));
    ASSERT_TRUE(reader.wait_jpegs(i, 20s)) << "frame " << i << " did not reach the reader";
  }
  EXPECT_EQ(server.clients(), 2u) << "the client that never reads left before the other "
                                     "had its frames: they waited for it";
  EXPECT_GT(server.frames_skipped(), 0u);
}

// A server on a free loopback port that admits one WebSocket client and greets it.
std::unique_ptr<WebServer> one_client_server() {
  mg_init_library(MG_FEATURES_WEBSOCKET);
  return std::make_unique<WebServer>(
      parse_listen_address("127.0.0.1", false), 0, 1, "<p>viewer</p>",
      [] { return std::string(R"({"type":"hello"})"); }, nullptr);
}

// More WebSockets than max_clients: the next one is answered 503 with a one-line reason, and
// gets in once a place is free.
TEST(WebServer, RefusesClientsBeyondTheLimitWith503) {
  const std::unique_ptr<WebServer> owned = one_client_server();
  WebServer& server = *owned;
  auto first = std::make_unique<Client>(server.port());
  ASSERT_FALSE(first->wait_type("hello").is_null());
  Socket second(server.port());
  ASSERT_TRUE(second.send(kHandshake));
  const std::string reply = second.read(10s);
  EXPECT_EQ(reply.rfind("HTTP/1.1 503 Service Unavailable\r\n", 0), 0u) << reply;
  EXPECT_EQ(server.clients(), 1u);
  first.reset();
  ASSERT_TRUE(soon([&] { return server.clients() == 0; }));
  Client third(server.port());
  EXPECT_FALSE(third.wait_type("hello").is_null());
}

// A closed client's place is free as soon as clients() no longer counts it: a viewer that
// reloads its page reconnects at once and must not be refused. Each round closes the only
// admitted client and connects another right after the count drops (the place used to be
// freed later, at the end of civetweb's request, and the newcomer could get a 503).
TEST(WebServer, AClosedClientsPlaceIsFreeAsSoonAsItIsNoLongerCounted) {
  const std::unique_ptr<WebServer> owned = one_client_server();
  WebServer& server = *owned;
  auto client = std::make_unique<Client>(server.port());
  ASSERT_FALSE(client->wait_type("hello").is_null());
  for (int round = 0; round < 5; ++round) {
    client.reset();
    ASSERT_TRUE(soon([&] { return server.clients() == 0; })) << "round " << round;
    client = std::make_unique<Client>(server.port());
    ASSERT_FALSE(client->wait_type("hello").is_null()) << "round " << round;
  }
}

}  // namespace web_server_test
}  // namespace multiray::app::viewer
