// stats.json's per-frame records, kept on disk as frames finish, so that a render's memory
// stays flat however many frames it has (a record is a few KB: 10^6 frames held in memory
// would take gigabytes). The records go to an anonymous file in the output folder (created
// and unlinked at once, so no way of ending the process leaves it behind, and it fills the
// disk the outputs go to, not /tmp); write() then streams the whole document atomically.
#pragma once

#include <cstdio>
#include <string>

#include <nlohmann/json.hpp>

namespace multiray::app {

class FrameSpool {
 public:
  // Throws InputError when no file can be made in `dir`.
  explicit FrameSpool(const std::string& dir);
  ~FrameSpool();
  FrameSpool(const FrameSpool&) = delete;
  FrameSpool& operator=(const FrameSpool&) = delete;

  // Appends one frame's record (throws InputError on a failed write, with the cause).
  void add(const nlohmann::json& record);
  size_t size() const { return count_; }

  // Writes `head` to `path` (write_file_atomically's guarantees) with a "frames" member
  // holding every record added, in order, formatted as dump_json(doc, 1) would, and a newline.
  // `head` must not have a "frames" member of its own.
  void write(const std::string& path, nlohmann::json head);

 private:
  std::string dir_;
  std::FILE* file_ = nullptr;
  size_t count_ = 0;
};

}  // namespace multiray::app
