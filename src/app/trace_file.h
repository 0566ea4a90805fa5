// --trace FILE: a trace (balance/trace.h) written frame by frame as frames finish.
#pragma once

#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "balance/trace.h"
#include "core/error.h"
#include "device/device.h"

namespace multiray::app {

class TraceFile {
 public:
  // Throws InputError when the file cannot be created.
  TraceFile(const std::string& path, const std::string& balancer,
            const std::vector<std::unique_ptr<Device>>& devices)
      : path_(path), out_(path) {
    if (!out_) throw InputError("cannot write trace '" + path + "'");
    std::vector<balance::TraceDevice> list;
    for (const auto& d : devices) list.push_back({d->info().name, d->info().emulated_speed});
    writer_ = std::make_unique<balance::TraceWriter>(out_, balancer, list);
  }
  balance::TraceWriter& writer() { return *writer_; }
  // Flushes and checks every write; throws InputError when any failed (e.g. a full disk).
  void close() {
    out_.close();
    if (!out_) throw InputError("writing trace '" + path_ + "' failed");
  }

 private:
  std::string path_;
  std::ofstream out_;
  std::unique_ptr<balance::TraceWriter> writer_;
};

}  // namespace multiray::app
