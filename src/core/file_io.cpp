#include "core/file_io.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "core/error.h"

namespace multiray {

namespace {

// A temporary name beside `path` (same folder, so rename() is atomic), unique per process
// and call.
std::string temp_name(const std::string& path) {
  static int counter = 0;
  return path + ".part-" + std::to_string(getpid()) + "-" + std::to_string(++counter);
}

[[noreturn]] void fail(const std::string& path, const std::string& temp, const char* what,
                       int err) {
  if (!temp.empty()) unlink(temp.c_str());
  throw InputError("cannot write '" + path + "': " + what + ": " + std::strerror(err));
}

// fsync + rename of a complete temporary file.
void commit(const std::string& path, const std::string& temp, int fd) {
  if (fsync(fd) != 0 && errno != EINVAL) {
    const int err = errno;
    close(fd);
    fail(path, temp, "flushing", err);
  }
  if (close(fd) != 0) fail(path, temp, "closing", errno);
  if (std::rename(temp.c_str(), path.c_str()) != 0) fail(path, temp, "renaming", errno);
}

// What a non-regular file is, for the error message.
const char* kind_of(mode_t mode) {
  if (S_ISDIR(mode)) return "a folder";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

}  // namespace

void check_output_file(const std::string& path, const std::string& option) {
  struct stat st {};
  if (stat(path.c_str(), &st) != 0) return;  // absent (or a dangling link): a new file
  if (S_ISREG(st.st_mode)) return;
  throw InputError(option + " '" + path + "' is " + kind_of(st.st_mode) +
                   "; outputs are written only to regular files or new names");
}

void write_file_atomically(const std::string& path, const void* data, size_t n) {
  check_output_file(path, "output");
  const std::string temp = temp_name(path);
  const int fd = open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) fail(path, "", "creating a temporary file", errno);
  const char* p = static_cast<const char*>(data);
  while (n > 0) {
    const ssize_t w = write(fd, p, n);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) {
      const int err = w < 0 ? errno : ENOSPC;
      close(fd);
      fail(path, temp, "writing", err);
    }
    p += w, n -= size_t(w);
  }
  commit(path, temp, fd);
}

void replace_file_atomically(const std::string& path,
                             const std::function<void(const std::string& temp)>& write) {
  check_output_file(path, "output");
  const std::string temp = temp_name(path);
  try {
    write(temp);
  } catch (...) {
    unlink(temp.c_str());
    throw;
  }
  const int fd = open(temp.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) fail(path, temp, "reopening the temporary file", errno);
  commit(path, temp, fd);
}

}  // namespace multiray
