#include "app/viewer/web_server.h"

#include <civetweb.h>
#include <poll.h>
#include <sys/socket.h>

#include <cerrno>
#include <thread>
#include <vector>

#include "app/viewer/connection_socket.h"
#include "core/error.h"

namespace multiray::app::viewer {

namespace {
// Whether `bytes` went out whole (mg_websocket_write returns the payload bytes written,
// fewer when a write timed out part-way, or the header's 2 bytes for an empty payload).
bool write_whole(mg_connection* conn, int opcode, const std::string& bytes) {
  const int r = mg_websocket_write(conn, opcode, bytes.data(), bytes.size());
  return bytes.empty() ? r > 0 : r == int(bytes.size());
}
}  // namespace

// One open WebSocket: its queue and the thread that sends from it. The thread is joined by
// on_ws_close, before civetweb reuses the connection.
struct WebServer::Peer {
  mg_connection* conn = nullptr;
  int fd = -1;  // the connection's socket, read by read_loop
  Outbox outbox;
  std::thread writer;
};

bool WebServer::has_ipv6() {
  mg_init_library(MG_FEATURES_WEBSOCKET);
  return mg_check_feature(MG_FEATURES_IPV6) != 0;
}

WebServer::WebServer(const ListenAddress& address, int port, int max_clients, std::string page,
                     Greeting greeting, OnMessage on_message)
    : page_(std::move(page)),
      greeting_(std::move(greeting)),
      on_message_(std::move(on_message)),
      max_clients_(max_clients) {
  if (port < 0 || port > 65535) throw InputError("--port must be in 0..65535");
  if (max_clients < 1 || max_clients > kMaxClientsLimit)
    throw InputError("--max-clients must be in 1.." + std::to_string(kMaxClientsLimit));
  mg_init_library(MG_FEATURES_WEBSOCKET);
  if (!mg_check_feature(MG_FEATURES_WEBSOCKET))
    throw InputError("this civetweb was built without WebSocket support");
  const std::string listen = address.listening_port(port);
  const std::string threads = std::to_string(max_clients + kSpareThreads);
  const std::string request_ms = std::to_string(kRequestTimeoutMs);
  // No websocket_timeout_ms / ping options: read_loop reads and pings the WebSockets.
  const char* options[] = {"listening_ports",
                           listen.c_str(),
                           "num_threads",
                           threads.c_str(),
                           "request_timeout_ms",
                           request_ms.c_str(),
                           "enable_keep_alive",
                           "no",
                           nullptr};
  mg_callbacks callbacks{};
  callbacks.end_request = &WebServer::on_end_request;
  ctx_ = mg_start(&callbacks, this, options);
  if (!ctx_) throw InputError("cannot listen on " + listen + " (in use, or not a local address?)");
  mg_server_port ports[4];
  const int n = mg_get_server_ports(ctx_, 4, ports);
  port_ = n > 0 ? ports[0].port : port;
  mg_set_request_handler(ctx_, "/", &WebServer::on_page, this);
  mg_set_websocket_handler(ctx_, "/ws", &WebServer::on_ws_connect, &WebServer::on_ws_ready,
                           &WebServer::on_ws_data, &WebServer::on_ws_close, this);
}

// Read loops are woken (their sockets shut for reading) and end; mg_stop then ends every
// connection, and their close handlers join the writer threads.
WebServer::~WebServer() {
  stopping_ = true;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& [id, peer] : clients_)
      if (peer->fd >= 0) shutdown(peer->fd, SHUT_RD);
  }
  if (ctx_) mg_stop(ctx_);
}

size_t WebServer::clients() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return clients_.size();
}

int WebServer::on_page(mg_connection* conn, void* self) {
  auto* s = static_cast<WebServer*>(self);
  const mg_request_info* info = mg_get_request_info(conn);
  if (std::string(info->local_uri) != "/") {
    mg_send_http_error(conn, 404, "%s", "not found");
    return 404;
  }
  mg_send_http_ok(conn, "text/html; charset=utf-8", (long long)s->page_.size());
  mg_write(conn, s->page_.data(), s->page_.size());
  return 200;
}

// Admits the WebSocket while fewer than max_clients are; otherwise answers 503 (before the
// handshake, so this is still plain HTTP) and declines it.
int WebServer::on_ws_connect(const mg_connection* conn, void* self) {
  auto* s = static_cast<WebServer*>(self);
  {
    std::lock_guard<std::mutex> lock(s->mutex_);
    if (s->admitted_.size() < size_t(s->max_clients_)) {
      s->admitted_.insert(conn);
      return 0;
    }
  }
  const std::string reason = "multiray view: " + std::to_string(s->max_clients_) +
                             " clients are connected, the most --max-clients allows\n";
  mg_printf(const_cast<mg_connection*>(conn),
            "HTTP/1.1 503 Service Unavailable\r\nContent-Type: text/plain\r\n"
            "Content-Length: %zu\r\nRetry-After: 5\r\nConnection: close\r\n\r\n%s",
            reason.size(), reason.c_str());
  return 1;
}

// Every request ends here, a WebSocket once it is closed or its handshake failed.
void WebServer::on_end_request(const mg_connection* conn, int) {
  auto* s = static_cast<WebServer*>(mg_get_user_data(mg_get_context(conn)));
  std::lock_guard<std::mutex> lock(s->mutex_);
  s->admitted_.erase(conn);
}

// Registers the client, then serves its WebSocket on this (civetweb's) thread until it
// closes. Afterwards the socket is shut for reading, so that civetweb's own reading, which
// follows, ends at once and closes the connection (on_ws_close).
void WebServer::on_ws_ready(mg_connection* conn, void* self) {
  auto* s = static_cast<WebServer*>(self);
  const mg_request_info* info = mg_get_request_info(conn);
  auto peer = std::make_shared<Peer>();
  peer->conn = conn;
  peer->fd = find_connection_socket(info->server_port, info->remote_addr, info->remote_port);
  // Not found only without /proc (not Linux): the client is not served (no greeting, no
  // frames), and civetweb's reading, whole frames, closes it at its first message.
  if (peer->fd < 0) return;
  if (s->greeting_) peer->outbox.push_text(s->greeting_());  // before any frame
  int id = 0;
  {  // counted before the greeting can arrive: a client that has it is in clients()
    std::lock_guard<std::mutex> lock(s->mutex_);
    id = s->next_id_++;
    s->clients_[id] = peer;
    s->ids_[conn] = id;
  }
  peer->writer = std::thread([p = peer.get()] { write_loop(*p); });
  if (!s->stopping_) s->read_loop(*peer, id);
  shutdown(peer->fd, SHUT_RD);
}

// Sends what the client's outbox holds until it is closed. A write that fails (the client
// left, or read nothing for kRequestTimeoutMs) ends the loop and closes the outbox; read_loop
// then ends the connection when its pings fail or go unanswered.
void WebServer::write_loop(Peer& peer) {
  std::vector<std::string> texts;
  std::shared_ptr<const OutFrame> frame;
  while (peer.outbox.take(texts, frame)) {
    bool ok = true;
    for (const std::string& t : texts)
      ok = ok && write_whole(peer.conn, MG_WEBSOCKET_OPCODE_TEXT, t);
    if (ok && frame)
      ok = write_whole(peer.conn, MG_WEBSOCKET_OPCODE_TEXT, frame->json) &&
           write_whole(peer.conn, MG_WEBSOCKET_OPCODE_BINARY, frame->jpeg);
    if (!ok) {
      peer.outbox.close();
      return;
    }
  }
}

WebServer::Answer WebServer::receive(int client, ws::Decoder& decoder, std::string_view bytes) {
  Answer a;
  decoder.pending.append(bytes);
  for (;;) {
    ws::Event e = ws::next_event(decoder);
    switch (e.kind) {
      case ws::Event::kNone:
        return a;
      case ws::Event::kMessage:
        if (e.opcode == ws::kText && on_message_) on_message_(client, e.payload);
        break;
      case ws::Event::kPing:
        a.frames.emplace_back(ws::kPong, std::move(e.payload));
        break;
      case ws::Event::kPong:
        break;                 // any bytes count as an answer (read_loop)
      case ws::Event::kClose:  // echo the code (§5.5.1)
        a.frames.emplace_back(ws::kClose, e.payload.size() >= 2
                                              ? e.payload.substr(0, 2)
                                              : ws::close_body(ws::kNormalClosure, ""));
        a.close = true;
        return a;
      case ws::Event::kRefuse:
        a.frames.emplace_back(ws::kClose, ws::close_body(e.refusal.code, e.refusal.reason));
        a.close = true;
        return a;
    }
  }
}

// Reads `peer`'s socket kReadBytes at a time into receive() and writes its answers, until
// the client closes or is refused, the socket fails, the server stops, or
// kMaxUnansweredPings pings sent kPingIntervalMs apart got no byte back.
void WebServer::read_loop(Peer& peer, int client) {
  ws::Decoder decoder;
  int unanswered = 0;
  char buf[ws::kReadBytes];
  while (!stopping_) {
    pollfd p{peer.fd, POLLIN, 0};
    const int r = poll(&p, 1, kPingIntervalMs);
    if (r < 0 && errno == EINTR) continue;
    if (r < 0) return;
    if (r == 0) {
      if (unanswered >= kMaxUnansweredPings) return;
      if (!write_whole(peer.conn, ws::kPing, "")) return;
      ++unanswered;
      continue;
    }
    const ssize_t n = recv(peer.fd, buf, sizeof buf, 0);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;
    unanswered = 0;
    Answer a;
    try {
      a = receive(client, decoder, std::string_view(buf, size_t(n)));
    } catch (...) {  // a defect; it must not end civetweb's thread (std::terminate)
      return;        // closes this client's connection
    }
    if (a.close) peer.outbox.close();  // no frame after ours but one being written
    for (const auto& [opcode, payload] : a.frames)
      if (!write_whole(peer.conn, opcode, payload)) return;
    if (a.close) return;
  }
}

// Reached only with bytes civetweb read before read_loop took the socket over (a client
// that sent frames before the handshake's answer, against RFC 6455 §4.1) or after it ended:
// the connection is closed.
int WebServer::on_ws_data(mg_connection*, int, char*, size_t, void*) { return 0; }

void WebServer::on_ws_close(const mg_connection* conn, void* self) {
  auto* s = static_cast<WebServer*>(self);
  std::shared_ptr<Peer> peer;
  {
    std::lock_guard<std::mutex> lock(s->mutex_);
    const auto it = s->ids_.find(conn);
    if (it == s->ids_.end()) return;
    peer = s->clients_[it->second];
    s->clients_.erase(it->second);
    s->ids_.erase(it);
    // Its place is free from now on, not from on_end_request, which civetweb calls only
    // after this returns (after the writer's join): a client reconnecting at once would
    // otherwise be refused with 503 while clients() already says 0.
    s->admitted_.erase(conn);
  }
  peer->outbox.close();
  peer->writer.join();  // waits out a write in progress (at most kRequestTimeoutMs)
  std::lock_guard<std::mutex> lock(s->mutex_);
  s->skipped_by_gone_ += peer->outbox.frames_skipped();
}

bool WebServer::send_text(int client, const std::string& text) {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = clients_.find(client);
  return it != clients_.end() && it->second->outbox.push_text(text);
}

void WebServer::broadcast_frame(std::shared_ptr<const OutFrame> frame) {
  std::lock_guard<std::mutex> lock(mutex_);
  for (const auto& [id, peer] : clients_) peer->outbox.push_frame(frame);
}

uint64_t WebServer::frames_skipped() const {
  std::lock_guard<std::mutex> lock(mutex_);
  uint64_t n = skipped_by_gone_;
  for (const auto& [id, peer] : clients_) n += peer->outbox.frames_skipped();
  return n;
}

}  // namespace multiray::app::viewer
