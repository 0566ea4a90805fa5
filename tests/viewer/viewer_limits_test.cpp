// `multiray view` under clients that misbehave (issue 31): sockets that connect and send
// nothing, a WebSocket that never reads, more clients than --max-clients; and --bind's
// addresses, parsed strictly.
#include <civetweb.h>
#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include "raw_socket.h"
#include "support/run_cli.h"
#include "viewer_process.h"
#include "ws_client.h"

namespace viewer_limits_test {

using multiray::testing::Client;
using multiray::testing::kHandshake;
using multiray::testing::Socket;
using multiray::testing::ViewerProcess;
using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

const char* kArgs = "--res 64x36 --spp 1 --bounces 2 --devices cpu:threads=1,cpu:threads=1";
bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// The page, over a raw socket: its status line, within `within`.
std::string get_page(int port, std::chrono::milliseconds within) {
  Socket s(port);
  s.send("GET / HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n");
  const std::string r = s.read(within, [](const std::string& t) { return has(t, "\r\n"); });
  return r.substr(0, r.find("\r\n"));
}

// Sockets that connect and say nothing each held one of civetweb's 4 threads for 30 s, so
// four of them locked everyone out. Now the server has threads to spare and closes such a
// socket after 5 s.
TEST(ViewerLimits, IdleSocketsDoNotLockOutClients) {
  mg_init_library(MG_FEATURES_WEBSOCKET);
  ViewerProcess viewer(kArgs);
  ASSERT_GT(viewer.port(), 0);
  std::vector<std::unique_ptr<Socket>> idle;
  for (int i = 0; i < 10; ++i) idle.push_back(std::make_unique<Socket>(viewer.port()));
  const auto opened = Clock::now();
  // Generous bounds that machine load will not reach, far below the old 30 s.
  EXPECT_EQ(get_page(viewer.port(), 10s), "HTTP/1.1 200 OK");
  Client c(viewer.port());
  ASSERT_TRUE(c.connected()) << c.error();
  EXPECT_FALSE(c.wait_type("frame", 10s).is_null());
  for (auto& s : idle) {
    s->read(std::chrono::duration_cast<std::chrono::milliseconds>(opened + 20s - Clock::now()));
    EXPECT_TRUE(s->closed_by_peer()) << "an idle socket stayed open for 20 s";
  }
  EXPECT_EQ(viewer.stop(), 128 + SIGINT);
}

// A WebSocket that never reads is dropped and its place freed (--max-clients 2: a third
// client gets in), while the other client keeps receiving frames. Before, nothing ever
// dropped it (the WebSocket timeout was an hour, without pings). That the others are
// served while it is still connected is web_server_test.cpp's.
TEST(ViewerLimits, AClientThatNeverReadsIsDroppedAndOthersKeepReceiving) {
  mg_init_library(MG_FEATURES_WEBSOCKET);
  ViewerProcess viewer(std::string("--max-clients 2 ") + kArgs);
  ASSERT_GT(viewer.port(), 0);
  Client reader(viewer.port());
  ASSERT_TRUE(reader.connected()) << reader.error();
  ASSERT_FALSE(reader.wait_type("frame").is_null());
  Socket stuck(viewer.port(), 4096);
  ASSERT_TRUE(stuck.ok() && stuck.send(kHandshake));
  const auto until = Clock::now() + 90s;
  bool admitted = false;
  while (!admitted && Clock::now() < until) {
    Client next(viewer.port());
    admitted = next.connected() && !next.wait_type("hello", 5s).is_null();
    if (!admitted) std::this_thread::sleep_for(500ms);
  }
  EXPECT_TRUE(admitted) << "the client that never reads kept its place for 90 s";
  const size_t before = reader.jpegs();
  EXPECT_TRUE(reader.wait_jpegs(before + 10, 20s)) << "the reading client stopped receiving";
  EXPECT_EQ(viewer.stop(), 128 + SIGINT);
}

// More clients than --max-clients: the next WebSocket gets a 503 with a one-line reason
// at once (before, clients beyond civetweb's 4 threads waited without an answer); the
// page is still served, and a place that frees up is taken again.
TEST(ViewerLimits, ClientsBeyondMaxClientsAreRefusedWith503) {
  mg_init_library(MG_FEATURES_WEBSOCKET);
  ViewerProcess viewer(std::string("--max-clients 2 ") + kArgs);
  ASSERT_GT(viewer.port(), 0);
  Client a(viewer.port());
  auto b = std::make_unique<Client>(viewer.port());
  ASSERT_FALSE(a.wait_type("hello").is_null());
  ASSERT_FALSE(b->wait_type("hello").is_null());
  Socket third(viewer.port());
  ASSERT_TRUE(third.send(kHandshake));
  const std::string reply = third.read(10s);
  EXPECT_EQ(reply.rfind("HTTP/1.1 503 Service Unavailable\r\n", 0), 0u) << reply;
  const std::string body = reply.substr(reply.find("\r\n\r\n") + 4);
  EXPECT_TRUE(has(body, "--max-clients")) << body;
  EXPECT_EQ(body.find('\n'), body.size() - 1) << "not one line: " << body;
  EXPECT_EQ(get_page(viewer.port(), 10s), "HTTP/1.1 200 OK");
  b.reset();
  const auto until = Clock::now() + 20s;
  bool admitted = false;
  while (!admitted && Clock::now() < until) {
    Client next(viewer.port());
    admitted = next.connected() && !next.wait_type("hello", 5s).is_null();
    if (!admitted) std::this_thread::sleep_for(200ms);
  }
  EXPECT_TRUE(admitted) << "a freed place was not given to the next client";
  EXPECT_EQ(viewer.stop(), 128 + SIGINT);
}

TEST(ViewerLimits, MaxClientsOutOfRangeIsRefused) {
  for (const char* bad : {"0", "257", "-1", "x", "1e3"}) {
    const auto r = multiray::testing::run_cli(
        MULTIRAY_BIN, std::string("view --port 0 --max-frames 1 --max-clients ") + bad);
    EXPECT_EQ(r.code, 2) << bad << ": " << r.out;
    EXPECT_TRUE(has(r.out, "--max-clients")) << r.out;
    EXPECT_EQ(r.out.find('\n'), r.out.size() - 1) << "not one line: " << r.out;
  }
}

// --exposure: auto (the default) or stops; anything else is one line, before any rendering.
TEST(ViewerLimits, ExposureIsAutoOrStops) {
  for (const char* bad : {"bright", "21", "nan"}) {
    const auto r = multiray::testing::run_cli(
        MULTIRAY_BIN, std::string("view --port 0 --max-frames 1 --exposure ") + bad);
    EXPECT_EQ(r.code, 2) << bad << ": " << r.out;
    EXPECT_TRUE(has(r.out, "--exposure")) << r.out;
  }
  const auto ok = multiray::testing::run_cli(
      MULTIRAY_BIN, "view --port 0 --max-frames 1 --res 16x8 --spp 1 --exposure -2");
  EXPECT_EQ(ok.code, 0) << ok.out;
}

// --bind took what civetweb's parser made of it: 256.0.0.0 listened on 0.0.0.0 while the
// URL said 256.0.0.0; ::1 was refused as "cannot listen".
TEST(ViewerBind, InvalidAddressesAreRefusedInOneLine) {
  for (const char* bad : {"256.0.0.0", "1.2.3", "01.2.3.4", "127.0.0.1:80", "example.com",
                          "fe80::1%lo", "''", "'1.2.3.4 '"}) {
    const auto r = multiray::testing::run_cli(
        MULTIRAY_BIN, std::string("view --port 0 --max-frames 1 --bind ") + bad);
    EXPECT_EQ(r.code, 2) << bad << ": " << r.out;
    EXPECT_TRUE(has(r.out, "--bind")) << r.out;
    EXPECT_EQ(r.out.find('\n'), r.out.size() - 1) << "not one line: " << r.out;
  }
  ViewerProcess local(std::string("--bind localhost ") + kArgs);
  EXPECT_GT(local.port(), 0) << "localhost is 127.0.0.1";
  // Stopped right after it printed its address: the Ctrl-C must not be lost (it was, when
  // it reached the session before its first frame; Session.StopRequestedBeforeRun...).
  EXPECT_EQ(local.stop(), 128 + SIGINT);
}

// IPv6 loopback: served at http://[::1]:PORT/ when civetweb has IPv6, else refused in one
// line that says so (Debian 12's libcivetweb1 1.15 is built without it).
TEST(ViewerBind, Ipv6LoopbackIsServedOrRefusedClearly) {
  if (!mg_check_feature(MG_FEATURES_IPV6)) {
    const auto r =
        multiray::testing::run_cli(MULTIRAY_BIN, "view --port 0 --max-frames 1 --bind ::1");
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_TRUE(has(r.out, "IPv6")) << r.out;
    EXPECT_EQ(r.out.find('\n'), r.out.size() - 1) << "not one line: " << r.out;
    return;
  }
  ViewerProcess viewer(std::string("--bind ::1 ") + kArgs);
  ASSERT_GT(viewer.port(), 0);
  EXPECT_EQ(viewer.url(), "http://[::1]:" + std::to_string(viewer.port()) + "/");
  Client c(viewer.port(), "::1");
  ASSERT_TRUE(c.connected()) << c.error();
  EXPECT_FALSE(c.wait_type("frame").is_null());
  EXPECT_EQ(viewer.stop(), 128 + SIGINT);
}

}  // namespace viewer_limits_test
