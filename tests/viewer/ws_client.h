// A WebSocket client of `multiray view` for the viewer tests (civetweb's client), collecting
// what the server sends.
#pragma once

#include <civetweb.h>

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <mutex>
#include <string>

#include <nlohmann/json.hpp>

namespace multiray::testing {

using namespace std::chrono_literals;

// A WebSocket client collecting what the server sends.
class Client {
 public:
  explicit Client(int port, const char* host = "127.0.0.1") {
    char error[256] = "";
    conn_ = mg_connect_websocket_client(host, port, 0, error, sizeof error, "/ws", nullptr,
                                        &Client::on_data, &Client::on_close, this);
    error_ = error;
  }
  ~Client() {
    if (conn_) mg_close_connection(conn_);
  }
  bool connected() const { return conn_ != nullptr; }
  const std::string& error() const { return error_; }
  void send(const std::string& text, int opcode = MG_WEBSOCKET_OPCODE_TEXT) {
    mg_websocket_client_write(conn_, opcode, text.data(), text.size());
  }
  // The next text message for which `pred` holds (earlier ones are dropped), within
  // `within`; null when none came.
  nlohmann::json wait(const std::function<bool(const nlohmann::json&)>& pred,
                      std::chrono::seconds within = 20s) {
    std::unique_lock<std::mutex> lock(mutex_);
    const auto until = std::chrono::steady_clock::now() + within;
    for (;;) {
      while (!texts_.empty()) {
        nlohmann::json j = nlohmann::json::parse(texts_.front(), nullptr, false);
        texts_.pop_front();
        if (!j.is_discarded() && pred(j)) return j;
      }
      if (arrived_.wait_until(lock, until) == std::cv_status::timeout) return nullptr;
    }
  }
  nlohmann::json wait_type(const std::string& type, std::chrono::seconds within = 20s) {
    return wait([&](const nlohmann::json& j) { return j.value("type", "") == type; }, within);
  }
  size_t jpegs() {
    std::lock_guard<std::mutex> lock(mutex_);
    return jpegs_;
  }
  // Whether `n` JPEGs in all have arrived within `within`.
  bool wait_jpegs(size_t n, std::chrono::seconds within) {
    std::unique_lock<std::mutex> lock(mutex_);
    return arrived_.wait_for(lock, within, [&] { return jpegs_ >= n; });
  }

 private:
  static int on_data(mg_connection* conn, int bits, char* data, size_t len, void* self) {
    auto* c = static_cast<Client*>(self);
    // The server pings a silent client and drops it after 6 pings unanswered (a browser
    // answers them by itself).
    if ((bits & 0xf) == MG_WEBSOCKET_OPCODE_PING)
      mg_websocket_client_write(conn, MG_WEBSOCKET_OPCODE_PONG, data, len);
    std::lock_guard<std::mutex> lock(c->mutex_);
    if ((bits & 0xf) == MG_WEBSOCKET_OPCODE_TEXT) c->texts_.emplace_back(data, len);
    if ((bits & 0xf) == MG_WEBSOCKET_OPCODE_BINARY && len > 2 && uint8_t(data[0]) == 0xff &&
        uint8_t(data[1]) == 0xd8)
      ++c->jpegs_;
    c->arrived_.notify_all();
    return 1;
  }
  static void on_close(const mg_connection*, void*) {}

  mg_connection* conn_ = nullptr;
  std::mutex mutex_;
  std::condition_variable arrived_;
  std::deque<std::string> texts_;
  size_t jpegs_ = 0;
  std::string error_;
};

}  // namespace multiray::testing
