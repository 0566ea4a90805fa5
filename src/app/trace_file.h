// --trace FILE: a trace (balance/trace.h) written frame by frame as frames finish, into a
// temporary file beside FILE that becomes FILE only when close() has checked every write.
#pragma once

#include <cstdio>
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
      : path_(path), temp_(path + ".part"), out_(temp_) {
    if (!out_) throw InputError("cannot write trace '" + path + "'");
    std::vector<balance::TraceDevice> list;
    for (const auto& d : devices) list.push_back({d->info().name, d->info().emulated_speed});
    writer_ = std::make_unique<balance::TraceWriter>(out_, balancer, list);
  }
  balance::TraceWriter& writer() { return *writer_; }
  // Flushes and checks every write; throws InputError when any failed (e.g. a full disk).
  void close() {
    out_.close();
    if (!out_ || std::rename(temp_.c_str(), path_.c_str()) != 0) {
      std::remove(temp_.c_str());
      throw InputError("writing trace '" + path_ + "' failed");
    }
  }

 private:
  std::string path_, temp_;
  std::ofstream out_;
  std::unique_ptr<balance::TraceWriter> writer_;
};

}  // namespace multiray::app
