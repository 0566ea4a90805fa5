// One client's queue of outgoing messages: texts in order up to a bound, the newest frame
// only, and a close that wakes the writer and refuses what comes later.
#include <gtest/gtest.h>

#include <thread>

#include "app/viewer/outbox.h"

namespace multiray::app::viewer {
namespace outbox_test {

std::shared_ptr<const OutFrame> frame(const std::string& name) {
  return std::make_shared<const OutFrame>(OutFrame{name, "jpeg"});
}

TEST(Outbox, KeepsTextsInOrderAndOnlyTheNewestFrame) {
  Outbox box;
  EXPECT_TRUE(box.push_text("hello"));
  EXPECT_TRUE(box.push_frame(frame("1")));
  EXPECT_TRUE(box.push_frame(frame("2")));
  EXPECT_TRUE(box.push_text("error"));
  EXPECT_TRUE(box.push_frame(frame("3")));
  std::vector<std::string> texts;
  std::shared_ptr<const OutFrame> f;
  ASSERT_TRUE(box.take(texts, f));
  EXPECT_EQ(texts, (std::vector<std::string>{"hello", "error"}));
  ASSERT_TRUE(f);
  EXPECT_EQ(f->json, "3");
  EXPECT_EQ(box.frames_skipped(), 2u);
}

TEST(Outbox, IsBoundedForAClientThatNeverReads) {
  Outbox box;
  for (size_t i = 0; i < Outbox::kMaxTexts; ++i) EXPECT_TRUE(box.push_text("e"));
  EXPECT_FALSE(box.push_text("one too many"));
  EXPECT_EQ(box.texts_dropped(), 1u);
  for (int i = 0; i < 1000; ++i) box.push_frame(frame(std::to_string(i)));
  EXPECT_EQ(box.frames_skipped(), 999u);
}

TEST(Outbox, CloseWakesTheWriterAndRefusesMore) {
  Outbox box;
  bool taken = true;
  std::thread writer([&] {
    std::vector<std::string> texts;
    std::shared_ptr<const OutFrame> f;
    taken = box.take(texts, f);
  });
  box.close();
  writer.join();
  EXPECT_FALSE(taken);
  EXPECT_TRUE(box.closed());
  EXPECT_FALSE(box.push_text("late"));
  EXPECT_FALSE(box.push_frame(frame("late")));
}

}  // namespace outbox_test
}  // namespace multiray::app::viewer
