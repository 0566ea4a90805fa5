// The live viewer's web server: one page at "/" and a WebSocket at "/ws", on civetweb
// (Debian's libcivetweb). Clients are numbered; messages from them arrive on civetweb's
// threads through `on_message`. Sends are serialised per connection; a client that
// vanished is simply gone from the set.
#pragma once

#include <functional>
#include <map>
#include <mutex>
#include <string>

struct mg_context;
struct mg_connection;

namespace multiray::app::viewer {

class WebServer {
 public:
  using OnMessage = std::function<void(int client, const std::string& text)>;
  using OnConnect = std::function<void(int client)>;

  // Listens on `bind`:`port` (port 0: any free port). Throws InputError when it cannot.
  WebServer(const std::string& bind, int port, std::string page, OnConnect on_connect,
            OnMessage on_message);
  ~WebServer();
  WebServer(const WebServer&) = delete;
  WebServer& operator=(const WebServer&) = delete;

  int port() const { return port_; }
  size_t clients() const;
  // False when the client is gone.
  bool send_text(int client, const std::string& text);
  void broadcast_text(const std::string& text);
  void broadcast_binary(const std::string& bytes);

 private:
  static int on_page(mg_connection* conn, void* self);
  static int on_ws_connect(const mg_connection* conn, void* self);
  static void on_ws_ready(mg_connection* conn, void* self);
  static int on_ws_data(mg_connection* conn, int bits, char* data, size_t len, void* self);
  static void on_ws_close(const mg_connection* conn, void* self);
  bool send(mg_connection* conn, int opcode, const std::string& bytes);

  std::string page_;
  OnConnect on_connect_;
  OnMessage on_message_;
  mg_context* ctx_ = nullptr;
  int port_ = 0;
  mutable std::mutex mutex_;
  std::map<int, mg_connection*> clients_;
  std::map<const mg_connection*, int> ids_;
  int next_id_ = 1;
};

}  // namespace multiray::app::viewer
