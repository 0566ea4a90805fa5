#include "app/frame_spool.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <vector>

#include "core/error.h"
#include "core/file_io.h"
#include "study/stats_json.h"

namespace multiray::app {

namespace {
// Stands for the records in the head's text; a user's string cannot produce this
// sequence (its quotes would be escaped), and "frames" is a key of the top level only once.
constexpr const char* kMarker = "@multiray-frames@";

[[noreturn]] void fail(const std::string& what, const std::string& where) {
  throw InputError("cannot " + what + " '" + where + "': " + std::strerror(errno));
}

void put(std::FILE* f, const std::string& text, const std::string& what,
         const std::string& where) {
  if (std::fwrite(text.data(), 1, text.size(), f) != text.size()) fail(what, where);
}
}  // namespace

FrameSpool::FrameSpool(const std::string& dir) : dir_(dir) {
  std::string name = dir + "/.multiray-frames-XXXXXX";
  const int fd = mkstemp(name.data());
  if (fd < 0) fail("keep frame records in", dir);
  unlink(name.c_str());  // anonymous from now on: gone when the process ends
  file_ = fdopen(fd, "w+");
  if (!file_) {
    close(fd);
    fail("keep frame records in", dir);
  }
}

FrameSpool::~FrameSpool() {
  if (file_) std::fclose(file_);
}

void FrameSpool::add(const nlohmann::json& record) {
  // Indented as an element of the top-level "frames" array: two spaces deeper. Raw
  // newlines in dump_json's text are structural (a string's are escaped).
  std::string text = study::dump_json(record, 1);
  std::string indented = count_ == 0 ? "\n  " : ",\n  ";
  for (const char c : text) indented += c == '\n' ? std::string("\n  ") : std::string(1, c);
  put(file_, indented, "keep frame records in", dir_);
  ++count_;
}

void FrameSpool::write(const std::string& path, nlohmann::json head) {
  head["frames"] = kMarker;
  const std::string text = study::dump_json(head, 1) + "\n";
  const std::string slot = std::string("\"frames\": \"") + kMarker + "\"";
  const size_t at = text.find(slot);
  if (at == std::string::npos) throw std::logic_error("frame spool: marker not found");
  if (std::fflush(file_) != 0) fail("write frame records in", dir_);
  replace_file_atomically(path, [&](const std::string& temp) {
    std::FILE* out = std::fopen(temp.c_str(), "wbx");
    if (!out) fail("write", path);
    try {
      put(out, text.substr(0, at) + "\"frames\": [", "write", path);
      std::rewind(file_);
      std::vector<char> buffer(1 << 16);
      size_t n = 0;
      while ((n = std::fread(buffer.data(), 1, buffer.size(), file_)) > 0)
        if (std::fwrite(buffer.data(), 1, n, out) != n) fail("write", path);
      if (std::ferror(file_)) fail("read frame records back for", path);
      put(out, std::string(count_ > 0 ? "\n ]" : "]") + text.substr(at + slot.size()), "write",
          path);
      std::fseek(file_, 0, SEEK_END);  // further records (none expected) append
    } catch (...) {
      std::fclose(out);
      throw;
    }
    if (std::fclose(out) != 0) fail("write", path);
  });
}

}  // namespace multiray::app
