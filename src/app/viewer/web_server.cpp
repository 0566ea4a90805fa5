#include "app/viewer/web_server.h"

#include <civetweb.h>

#include "core/error.h"

namespace multiray::app::viewer {

namespace {
constexpr size_t kMaxIncoming = 4096;  // longer messages are answered with an error
}

WebServer::WebServer(const std::string& bind, int port, std::string page, OnConnect on_connect,
                     OnMessage on_message)
    : page_(std::move(page)),
      on_connect_(std::move(on_connect)),
      on_message_(std::move(on_message)) {
  if (port < 0 || port > 65535) throw InputError("--port must be in 0..65535");
  mg_init_library(MG_FEATURES_WEBSOCKET);
  if (!mg_check_feature(MG_FEATURES_WEBSOCKET))
    throw InputError("this civetweb was built without WebSocket support");
  const std::string listen = bind + ":" + std::to_string(port);
  const char* options[] = {"listening_ports",      listen.c_str(), "num_threads", "4",
                           "websocket_timeout_ms", "3600000",      nullptr};
  mg_callbacks callbacks{};
  ctx_ = mg_start(&callbacks, this, options);
  if (!ctx_) throw InputError("cannot listen on " + listen + " (in use, or not a local address?)");
  mg_server_port ports[4];
  const int n = mg_get_server_ports(ctx_, 4, ports);
  port_ = n > 0 ? ports[0].port : port;
  mg_set_request_handler(ctx_, "/", &WebServer::on_page, this);
  mg_set_websocket_handler(ctx_, "/ws", &WebServer::on_ws_connect, &WebServer::on_ws_ready,
                           &WebServer::on_ws_data, &WebServer::on_ws_close, this);
}

WebServer::~WebServer() {
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

int WebServer::on_ws_connect(const mg_connection*, void*) { return 0; }  // accept

void WebServer::on_ws_ready(mg_connection* conn, void* self) {
  auto* s = static_cast<WebServer*>(self);
  int id;
  {
    std::lock_guard<std::mutex> lock(s->mutex_);
    id = s->next_id_++;
    s->clients_[id] = conn;
    s->ids_[conn] = id;
  }
  if (s->on_connect_) s->on_connect_(id);
}

int WebServer::on_ws_data(mg_connection* conn, int bits, char* data, size_t len, void* self) {
  auto* s = static_cast<WebServer*>(self);
  const int opcode = bits & 0xf;
  if (opcode == MG_WEBSOCKET_OPCODE_CONNECTION_CLOSE) return 0;
  if (opcode != MG_WEBSOCKET_OPCODE_TEXT) return 1;  // pings, binary: ignored
  int id = 0;
  {
    std::lock_guard<std::mutex> lock(s->mutex_);
    const auto it = s->ids_.find(conn);
    if (it == s->ids_.end()) return 0;
    id = it->second;
  }
  if (len > kMaxIncoming) {
    s->send_text(id, R"({"type":"error","message":"message longer than 4096 bytes"})");
    return 1;
  }
  if (s->on_message_) s->on_message_(id, std::string(data, len));
  return 1;
}

void WebServer::on_ws_close(const mg_connection* conn, void* self) {
  auto* s = static_cast<WebServer*>(self);
  std::lock_guard<std::mutex> lock(s->mutex_);
  const auto it = s->ids_.find(conn);
  if (it == s->ids_.end()) return;
  s->clients_.erase(it->second);
  s->ids_.erase(it);
}

// Sends hold mutex_ throughout, so a connection cannot be closed and freed by civetweb's
// close handler while it is being written to (a slow client thus delays the other
// clients' frames and the close of others, never the rendering).
bool WebServer::send(mg_connection* conn, int opcode, const std::string& bytes) {
  mg_lock_connection(conn);
  const int r = mg_websocket_write(conn, opcode, bytes.data(), bytes.size());
  mg_unlock_connection(conn);
  return r > 0;
}

bool WebServer::send_text(int client, const std::string& text) {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = clients_.find(client);
  return it != clients_.end() && send(it->second, MG_WEBSOCKET_OPCODE_TEXT, text);
}

void WebServer::broadcast_text(const std::string& text) {
  std::lock_guard<std::mutex> lock(mutex_);
  for (const auto& [id, conn] : clients_) send(conn, MG_WEBSOCKET_OPCODE_TEXT, text);
}

void WebServer::broadcast_binary(const std::string& bytes) {
  std::lock_guard<std::mutex> lock(mutex_);
  for (const auto& [id, conn] : clients_) send(conn, MG_WEBSOCKET_OPCODE_BINARY, bytes);
}

}  // namespace multiray::app::viewer
