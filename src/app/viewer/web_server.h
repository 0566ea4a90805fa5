// The live viewer's web server: one page at "/" and a WebSocket at "/ws", on civetweb
// (Debian's libcivetweb). Clients are numbered; messages from them arrive on civetweb's
// threads through `on_message`.
//
// Nothing a client does holds up the others or the render: each client has its own
// bounded Outbox and a writer thread that sends from it, so a client that reads slowly
// skips frames and one that stops reading is dropped (its writes time out), while the
// others keep receiving. At most `max_clients` WebSockets are open at once; one more is
// refused with HTTP 503 and a one-line reason. civetweb serves each connection on a thread
// of its own, so it gets max_clients + kSpareThreads threads: the spare ones serve the page,
// refusals and sockets that connect and send nothing (closed after kRequestTimeoutMs).
//
// civetweb does the HTTP upgrade; then the connection's thread reads the socket itself
// (read_loop): civetweb would read a whole frame into memory before any limit applied. Frames
// are decoded by ws_frames.h under RFC 6455: a frame declaring more than 4096 bytes is
// refused from its header (close 1009), a protocol violation closes with 1002, text that is
// not UTF-8 with 1007. Memory per connection: one 4 KB read buffer and ws::Decoder's bound.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "app/viewer/listen_address.h"
#include "app/viewer/outbox.h"
#include "app/viewer/ws_frames.h"

struct mg_context;
struct mg_connection;

namespace multiray::app::viewer {

class WebServer {
 public:
  using OnMessage = std::function<void(int client, const std::string& text)>;
  using Greeting = std::function<std::string()>;  // the first message to every client

  static constexpr int kMaxClientsLimit = 256;  // --max-clients range: 1..kMaxClientsLimit
  static constexpr int kSpareThreads = 8;
  // A connection's request must arrive within this, and a write that makes no progress
  // for this long fails (the client is dropped).
  static constexpr int kRequestTimeoutMs = 5000;
  // An open WebSocket silent this long is pinged; it is closed after kMaxUnansweredPings.
  static constexpr int kPingIntervalMs = 5000;
  static constexpr int kMaxUnansweredPings = 6;

  // Whether the civetweb library can listen on IPv6 addresses.
  static bool has_ipv6();

  // Listens on `address`:`port` (port 0: any free port). Throws InputError when it cannot.
  WebServer(const ListenAddress& address, int port, int max_clients, std::string page,
            Greeting greeting, OnMessage on_message);
  ~WebServer();
  WebServer(const WebServer&) = delete;
  WebServer& operator=(const WebServer&) = delete;

  int port() const { return port_; }
  size_t clients() const;
  // Queues `text` for `client`; false when the client is gone or its queue is full.
  bool send_text(int client, const std::string& text);
  // Queues `frame` for every client, replacing a frame a client has not started to send.
  void broadcast_frame(std::shared_ptr<const OutFrame> frame);
  // Frames not sent to a client because a newer one replaced them, summed over clients.
  uint64_t frames_skipped() const;

  // What the server answers to `bytes` (at most ws::kReadBytes) from `client`'s socket,
  // decoded by that connection's `decoder`: frames to send back (opcode, payload: pongs, a
  // close frame) and whether to close the connection after them. Each text message goes to
  // `on_message`; binary messages are ignored. Public so that the fuzz target drives the
  // same path with raw frames.
  struct Answer {
    std::vector<std::pair<int, std::string>> frames;
    bool close = false;
  };
  Answer receive(int client, ws::Decoder& decoder, std::string_view bytes);

 private:
  struct Peer;
  static int on_page(mg_connection* conn, void* self);
  static int on_ws_connect(const mg_connection* conn, void* self);
  static void on_ws_ready(mg_connection* conn, void* self);
  static int on_ws_data(mg_connection* conn, int bits, char* data, size_t len, void* self);
  static void on_ws_close(const mg_connection* conn, void* self);
  static void on_end_request(const mg_connection* conn, int status);
  static void write_loop(Peer& peer);
  void read_loop(Peer& peer, int client);

  std::string page_;
  Greeting greeting_;
  OnMessage on_message_;
  int max_clients_ = 0;
  mg_context* ctx_ = nullptr;
  int port_ = 0;
  mutable std::mutex mutex_;  // guards the fields below
  std::map<int, std::shared_ptr<Peer>> clients_;
  std::map<const mg_connection*, int> ids_;
  // WebSocket requests let in by on_ws_connect and not yet ended (on_end_request): what
  // --max-clients counts, so that a handshake in progress holds its place.
  std::set<const mg_connection*> admitted_;
  uint64_t skipped_by_gone_ = 0;       // frames_skipped() of clients that left
  std::atomic<bool> stopping_{false};  // set by the destructor: read loops end
  int next_id_ = 1;
};

}  // namespace multiray::app::viewer
