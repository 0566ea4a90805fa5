#include "core/scene_files.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <system_error>

#include "core/error.h"

namespace multiray {

namespace fs = std::filesystem;

namespace detail {

std::string file_name(const std::string& path) {
  const std::string name = fs::path(path).filename().string();
  return name.empty() ? path : name;
}

void fail(const std::string& path, const std::string& what) {
  std::string line;
  bool pending_break = false;
  for (char c : what) {
    if (c == '\n' || c == '\r') {
      pending_break = !line.empty();
      continue;
    }
    if (pending_break) line += "; ";
    pending_break = false;
    line += c;
  }
  throw InputError(path + ": " + line);
}

void warn(const LoadOptions& options, const std::string& path, const std::string& what) {
  const std::string line = path + ": " + what;
  if (options.warn)
    options.warn(line);
  else
    std::fprintf(stderr, "multiray: warning: %s\n", line.c_str());
}

}  // namespace detail

namespace {

// Whether canonical path `p` is `root` or lies below it (compared by components, so
// "/a/bc" is not inside "/a/b").
bool inside(const fs::path& root, const fs::path& p) {
  auto q = p.begin();
  for (auto r = root.begin(); r != root.end(); ++r, ++q)
    if (q == p.end() || *q != *r) return false;
  return true;
}

// Closes a file descriptor when it goes out of scope.
struct Fd {
  int fd;
  ~Fd() {
    if (fd >= 0) ::close(fd);
  }
};

}  // namespace

SceneFiles::SceneFiles(const std::string& scene_path, const LoadOptions& options)
    : path_(scene_path), options_(options) {
  const fs::path parent = fs::path(scene_path).parent_path();
  std::error_code ec;
  root_ = fs::canonical(parent.empty() ? fs::path(".") : parent, ec);
  if (ec) root_.clear();
}

std::string SceneFiles::read_scene_file() {
  std::string data, why;
  if (!read_checked(path_, /*named=*/false, &data, &why)) detail::fail(path_, why);
  if (data.empty()) detail::fail(path_, "file is empty");
  return data;
}

bool SceneFiles::read(const std::string& path, std::string* out, std::string* why) {
  return read_checked(path, /*named=*/true, out, why);
}

bool SceneFiles::read(const std::string& path, std::vector<unsigned char>* out, std::string* why) {
  return read_checked(path, /*named=*/true, out, why);
}

// Every check that can be made without opening the file comes first (stat, realpath):
// opening a FIFO for reading blocks until a writer appears. The file is then opened
// non-blocking and fstat() must show the same regular file, so a file swapped for a FIFO
// in between is refused too.
template <class Bytes>
bool SceneFiles::read_checked(const std::string& path, bool named, Bytes* out, std::string* why) {
  // Named files are shown as the scene names them: relative to its folder.
  const std::string prefix = fs::path(path_).parent_path().string() + "/";
  const bool under = prefix.size() > 1 && path.compare(0, prefix.size(), prefix) == 0;
  std::string name = "file";
  if (named) {
    name = path.substr(under ? prefix.size() : 0);
    name.insert(name.begin(), '\'');
    name.push_back('\'');
  }
  auto refuse = [&](const std::string& problem) {
    *why = name + " " + problem;
    return false;
  };
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    return refuse(errno == ENOENT ? "not found"
                                  : std::string("cannot be examined: ") + std::strerror(errno));
  if (!S_ISREG(st.st_mode)) return refuse("is not a regular file");
  if (named && !options_.allow_outside) {
    std::error_code ec;
    const fs::path real = fs::canonical(path, ec);
    if (ec) return refuse("cannot be resolved: " + ec.message());
    if (root_.empty() || !inside(root_, real))
      return refuse("lies outside the scene's folder '" + root_.string() + "' (it is '" +
                    real.string() + "')");
  }
  const uint64_t limit = options_.max_total_bytes;
  const uint64_t left = used_ < limit ? limit - used_ : 0;
  auto too_big = [&](uint64_t size) {
    return refuse("is " + std::to_string(size) + " bytes, more than " +
                  (used_ > 0 ? "the " + std::to_string(left) + " bytes left of " : "") + "the " +
                  std::to_string(limit) + "-byte limit for one scene");
  };
  if (uint64_t(st.st_size) > left) return too_big(uint64_t(st.st_size));

  Fd f{::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC)};
  if (f.fd < 0) return refuse(std::string("cannot be opened: ") + std::strerror(errno));
  struct stat now {};
  if (::fstat(f.fd, &now) != 0 || !S_ISREG(now.st_mode) || now.st_dev != st.st_dev ||
      now.st_ino != st.st_ino)
    return refuse("changed while being opened");
  const uint64_t size = uint64_t(now.st_size);
  if (size > left) return too_big(size);
  out->resize(size_t(size));
  size_t got = 0;
  while (got < out->size()) {
    const ssize_t n = ::read(f.fd, out->data() + got, out->size() - got);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return refuse(std::string("cannot be read: ") + std::strerror(errno));
    if (n == 0) break;  // the file shrank since fstat()
    got += size_t(n);
  }
  out->resize(got);
  used_ += got;
  if (options_.on_read) options_.on_read(path, content_hash(out->data(), out->size()));
  return true;
}

uint64_t content_hash(const void* data, size_t size, uint64_t seed) {
  const auto* bytes = static_cast<const unsigned char*>(data);
  uint64_t h = seed;
  for (size_t i = 0; i < size; ++i) h = (h ^ bytes[i]) * 0x100000001b3ull;
  return h;
}

}  // namespace multiray
