// Runs a load that must return quickly (refusals happen before anything is opened or
// built) and fails the test, instead of hanging it, when it does not.
#pragma once

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <future>
#include <memory>
#include <string>
#include <thread>

#include "core/error.h"

namespace multiray::test {

// What a guarded call did: returned, or threw (an InputError or something else).
struct Outcome {
  bool returned = false;
  bool input_error = false;
  std::string message;  // what() of the exception
};

// Calls `fn` on its own thread and waits up to 10 s. A std::async future would block in
// its destructor on a call stuck in open() of a FIFO, so the thread is detached and a
// timeout ends this test process (one test per process under ctest) after recording the
// failure.
inline Outcome within_10s(const std::function<void()>& fn) {
  auto result = std::make_shared<std::promise<Outcome>>();
  std::future<Outcome> done = result->get_future();
  std::thread([result, fn] {
    Outcome o;
    try {
      fn();
      o.returned = true;
    } catch (const InputError& e) {
      o.input_error = true;
      o.message = e.what();
    } catch (const std::exception& e) {
      o.message = e.what();
    }
    result->set_value(o);
  }).detach();
  if (done.wait_for(std::chrono::seconds(10)) != std::future_status::ready) {
    ADD_FAILURE() << "the call did not return within 10 s (blocked or running away)";
    std::fflush(stdout);
    std::fflush(stderr);
    std::_Exit(1);
  }
  return done.get();
}

// Expects `o` to be an InputError of one line containing every string in `words`.
inline void expect_input_error(const Outcome& o, std::initializer_list<std::string> words) {
  ASSERT_TRUE(o.input_error) << (o.returned ? "no error" : "not an InputError: " + o.message);
  EXPECT_EQ(o.message.find('\n'), std::string::npos) << o.message;
  for (const std::string& w : words)
    EXPECT_NE(o.message.find(w), std::string::npos) << "'" << w << "' not in: " << o.message;
}

}  // namespace multiray::test
