// The folder a run writes its frames and stats.json into, held for the whole run.
#pragma once

#include <functional>
#include <string>

namespace multiray {

// Made ready before anything loads or renders, in this order:
//  1. created if missing;
//  2. locked: an exclusive flock() on the folder itself (no lock file is left behind; the
//     kernel releases it when the process ends, however it ends), so a second run into the
//     same folder is refused at once instead of interleaving its frames with the first's;
//  3. checked writable, by creating and removing a file in it (permissions alone do not
//     tell: root ignores them, and a read-only mount or a full quota is only seen by trying);
//  4. an earlier run's outputs (the files whose names `is_output` accepts: by default
//     stats.json and frame_*) are refused, or with `overwrite` removed (exactly those
//     files), so the folder never mixes two runs.
// Every failure is an InputError naming the folder (and `option`) with the cause.
class OutputFolder {
 public:
  using NameFilter = std::function<bool(const std::string& file_name)>;
  OutputFolder(const std::string& dir, bool overwrite, const std::string& option = "--out",
               const NameFilter& is_output = {});
  ~OutputFolder();
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;

  const std::string& path() const { return dir_; }

 private:
  std::string dir_;
  int fd_ = -1;  // the open folder, holding the lock
};

}  // namespace multiray
