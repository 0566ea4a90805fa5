// --trace FILE: a trace (balance/trace.h) written frame by frame as frames finish, into a
// temporary file beside FILE that becomes FILE only when close() has checked every write.
#pragma once

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "balance/trace.h"
#include "core/error.h"
#include "core/file_io.h"
#include "device/device.h"

namespace multiray::study {

class TraceFile {
 public:
  // Throws InputError when FILE is not a regular file or a new name (check_output_file),
  // or cannot be created.
  TraceFile(const std::string& path, const std::string& balancer,
            const std::vector<std::unique_ptr<Device>>& devices)
      : path_(path), temp_(path + ".part-" + std::to_string(getpid())) {
    check_output_file(path, "--trace");
    out_.open(temp_, std::ios::binary | std::ios::trunc);
    if (!out_) throw InputError("cannot write trace '" + path + "': " + std::strerror(errno));
    std::vector<balance::TraceDevice> list;
    for (const auto& d : devices) list.push_back({d->info().name, d->info().emulated_speed});
    writer_ = std::make_unique<balance::TraceWriter>(out_, balancer, list);
  }
  ~TraceFile() {
    if (!closed_) std::remove(temp_.c_str());
  }
  // Appends a frame; the first failed write's cause is kept for close().
  void frame(const balance::FrameStats& stats,
             const std::vector<balance::DeviceCostModel>& models = {}) {
    writer_->frame(stats, models);
    out_.flush();
    if (!out_ && cause_.empty()) cause_ = std::strerror(errno);
  }
  // Flushes and checks every write, then renames the file into place; throws InputError
  // naming the cause when any write failed (e.g. a full disk).
  void close() {
    closed_ = true;
    out_.close();
    if (!out_ && cause_.empty()) cause_ = std::strerror(errno);
    if (cause_.empty() && std::rename(temp_.c_str(), path_.c_str()) != 0)
      cause_ = std::string("renaming: ") + std::strerror(errno);
    if (cause_.empty()) return;
    std::remove(temp_.c_str());
    throw InputError("writing trace '" + path_ + "' failed: " + cause_);
  }

 private:
  std::string path_, temp_, cause_;
  std::ofstream out_;
  std::unique_ptr<balance::TraceWriter> writer_;
  bool closed_ = false;
};

}  // namespace multiray::study
