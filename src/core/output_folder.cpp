#include "core/output_folder.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <vector>

#include "core/error.h"

namespace multiray {

namespace {

namespace fs = std::filesystem;

// Creating and removing a file is the one reliable test of writability.
void check_writable(const std::string& dir, const std::string& option) {
  std::string probe = dir + "/.multiray-write-test-XXXXXX";
  const int fd = mkstemp(probe.data());
  if (fd < 0) throw InputError(option + " '" + dir + "' is not writable: " + std::strerror(errno));
  close(fd);
  unlink(probe.c_str());
}

// The earlier run's outputs in `dir`: the files `is_output` accepts.
std::vector<fs::path> earlier_outputs(const std::string& dir, const std::string& option,
                                      const OutputFolder::NameFilter& is_output) {
  std::error_code ec;
  std::vector<fs::path> earlier;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    if (is_output(name)) earlier.push_back(e.path());
  }
  if (ec) throw InputError("cannot read " + option + " '" + dir + "': " + ec.message());
  return earlier;
}

}  // namespace

OutputFolder::OutputFolder(const std::string& dir, bool overwrite, const std::string& option,
                           const NameFilter& is_output)
    : dir_(dir) {
  const NameFilter outputs = is_output ? is_output : [](const std::string& name) {
    return name == "stats.json" || name.rfind("frame_", 0) == 0;
  };
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw InputError("cannot create " + option + " folder '" + dir + "': " + ec.message());
  fd_ = open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd_ < 0)
    throw InputError("cannot open " + option + " folder '" + dir + "': " + std::strerror(errno));
  if (flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    const int err = errno;
    close(fd_);
    if (err == EWOULDBLOCK)
      throw InputError(option + " '" + dir +
                       "' is in use by another multiray run; wait for it or choose another "
                       "folder");
    throw InputError("cannot lock " + option + " folder '" + dir + "': " + std::strerror(err));
  }
  try {
    check_writable(dir, option);
    const std::vector<fs::path> earlier = earlier_outputs(dir, option, outputs);
    if (earlier.empty()) return;
    if (!overwrite)
      throw InputError(option + " '" + dir + "' holds an earlier run's outputs (" +
                       earlier.front().filename().string() +
                       ", ...); pass --overwrite to replace them, or choose another folder");
    for (const fs::path& p : earlier)
      if (!fs::remove(p, ec) || ec)
        throw InputError("cannot remove '" + p.string() + "': " + ec.message());
  } catch (...) {
    close(fd_);
    throw;
  }
}

OutputFolder::~OutputFolder() { close(fd_); }  // closing releases the lock

}  // namespace multiray
