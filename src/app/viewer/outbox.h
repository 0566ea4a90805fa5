// What is waiting to be sent to one viewer client, bounded so that a client that reads
// slowly (or never) costs a fixed amount of memory and delays nobody else: up to
// kMaxTexts text messages (hello, error replies) and the newest frame only; a frame not
// yet taken when a newer one arrives is replaced (skipped for this client). Thread-safe:
// the server pushes, the client's writer thread takes.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace multiray::app::viewer {

// One frame as sent: its measurements (JSON text), then its picture (JPEG bytes). Shared by
// every client's outbox.
struct OutFrame {
  std::string json, jpeg;
};

class Outbox {
 public:
  static constexpr size_t kMaxTexts = 64;

  // False when the text was dropped: the outbox is closed or already holds kMaxTexts.
  bool push_text(std::string text);
  // Keeps `frame` as the one to send next; false when closed. Counts a frame it replaces.
  bool push_frame(std::shared_ptr<const OutFrame> frame);
  // Waits until something is queued or the outbox is closed. Moves the queued texts (in
  // order) into `texts` and the frame (or null) into `frame`, texts first to be sent.
  // False, with nothing moved, once closed.
  bool take(std::vector<std::string>& texts, std::shared_ptr<const OutFrame>& frame);
  // Wakes take(); later pushes are refused. Idempotent.
  void close();
  bool closed() const;
  uint64_t frames_skipped() const;
  uint64_t texts_dropped() const;

 private:
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::string> texts_;
  std::shared_ptr<const OutFrame> frame_;
  bool closed_ = false;
  uint64_t frames_skipped_ = 0, texts_dropped_ = 0;
};

}  // namespace multiray::app::viewer
