#include "scene/assimp_files.h"

#include <cctype>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <system_error>

namespace multiray::detail {

namespace fs = std::filesystem;

size_t ByteStream::Read(void* out, size_t size, size_t count) {
  if (size == 0 || count == 0 || out == nullptr) return 0;
  const size_t whole = std::min(count, (bytes_.size() - pos_) / size);  // whole elements only
  std::memcpy(out, bytes_.data() + pos_, whole * size);
  pos_ += whole * size;
  return whole;
}

aiReturn ByteStream::Seek(size_t offset, aiOrigin origin) {
  size_t base = 0;
  if (origin == aiOrigin_CUR) base = pos_;
  if (origin == aiOrigin_END) {
    if (offset > bytes_.size()) return aiReturn_FAILURE;
    pos_ = bytes_.size() - offset;
    return aiReturn_SUCCESS;
  }
  if (offset > bytes_.size() - base) return aiReturn_FAILURE;
  pos_ = base + offset;
  return aiReturn_SUCCESS;
}

bool SceneFileSystem::Exists(const char* path) const {
  if (path == nullptr) return false;
  if (files_->scene_path() == path) return true;
  std::error_code ec;
  return fs::is_regular_file(fs::path(path), ec);
}

Assimp::IOStream* SceneFileSystem::Open(const char* path, const char* mode) {
  if (path == nullptr || mode == nullptr || std::strpbrk(mode, "wa+") != nullptr) return nullptr;
  if (files_->scene_path() == path) return new ByteStream(scene_bytes_);
  std::vector<unsigned char> bytes;
  std::string why;
  if (!files_->read(path, &bytes, &why)) {
    if (first_refusal_.empty()) first_refusal_ = why;
    return nullptr;
  }
  return new ByteStream(std::move(bytes));
}

namespace {

// Skips spaces, line ends and '#' comment lines, as assimp's OFF reader does.
void next_token(const std::string& t, size_t* i) {
  for (;;) {
    while (*i < t.size() && std::isspace(static_cast<unsigned char>(t[*i]))) ++*i;
    if (*i >= t.size() || t[*i] != '#') return;
    while (*i < t.size() && t[*i] != '\n') ++*i;
  }
}

// assimp's strtoul10: decimal digits into an unsigned int, wrapping.
unsigned int wrapped_count(const std::string& t, size_t* i) {
  unsigned int v = 0;
  for (; *i < t.size() && t[*i] >= '0' && t[*i] <= '9'; ++*i) v = v * 10u + unsigned(t[*i] - '0');
  return v;
}

}  // namespace

void check_off_counts(const std::string& path, const std::string& text) {
  size_t i = 0;
  next_token(text, &i);
  bool dimension = false;
  for (const char* flag : {"ST", "C", "N", "4", "n"})
    if (text.compare(i, std::strlen(flag), flag) == 0) {
      i += std::strlen(flag);
      dimension = flag[0] == 'n';
    }
  if (text.compare(i, 3, "OFF") == 0) i += 3;
  next_token(text, &i);
  if (dimension) {
    wrapped_count(text, &i);
    next_token(text, &i);
  }
  const unsigned int vertices = wrapped_count(text, &i);
  next_token(text, &i);
  const unsigned int faces = wrapped_count(text, &i);
  if (uint64_t(vertices) > text.size() || uint64_t(faces) > text.size())
    fail(path, "the OFF header announces " + std::to_string(vertices) + " vertices and " +
                   std::to_string(faces) + " faces, more lines than the file's " +
                   std::to_string(text.size()) + " bytes can hold");
}

}  // namespace multiray::detail

// Debian's libassimp is built with ASSIMP_BUILD_DEBUG, so its internal consistency checks
// (ai_assert) are live and end the whole process with std::abort() on malformed input
// (4 KB of noise named .x trips one in the triangulation step). assimp 5.2 exports
// aiAssertViolation but not the setAiAssertHandler of later versions, and calls it
// through the PLT, so this definition in the executable takes the library's place: it
// throws instead, the import unwinds, and load_assimp() reports an InputError. (An
// assertion inside a noexcept function of assimp would still terminate.)
namespace Assimp {
void aiAssertViolation(const char* expression, const char* file, int line) {
  throw std::runtime_error(std::string("internal check failed (") + (file ? file : "?") + ":" +
                           std::to_string(line) + ": " + (expression ? expression : "?") + ")");
}
}  // namespace Assimp
