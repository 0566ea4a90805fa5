#include "app/viewer/outbox.h"

namespace multiray::app::viewer {

bool Outbox::push_text(std::string text) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (closed_ || texts_.size() >= kMaxTexts) {
      ++texts_dropped_;
      return false;
    }
    texts_.push_back(std::move(text));
  }
  wake_.notify_one();
  return true;
}

bool Outbox::push_frame(std::shared_ptr<const OutFrame> frame) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (closed_) return false;
    if (frame_) ++frames_skipped_;
    frame_ = std::move(frame);
  }
  wake_.notify_one();
  return true;
}

bool Outbox::take(std::vector<std::string>& texts, std::shared_ptr<const OutFrame>& frame) {
  std::unique_lock<std::mutex> lock(mutex_);
  wake_.wait(lock, [&] { return closed_ || !texts_.empty() || frame_; });
  if (closed_) return false;
  texts.assign(std::make_move_iterator(texts_.begin()), std::make_move_iterator(texts_.end()));
  texts_.clear();
  frame = std::move(frame_);
  frame_.reset();
  return true;
}

void Outbox::close() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    closed_ = true;
    texts_.clear();
    frame_.reset();
  }
  wake_.notify_all();
}

bool Outbox::closed() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return closed_;
}

uint64_t Outbox::frames_skipped() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return frames_skipped_;
}

uint64_t Outbox::texts_dropped() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return texts_dropped_;
}

}  // namespace multiray::app::viewer
