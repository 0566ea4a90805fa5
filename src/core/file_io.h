// Output files that are never half-written: every write goes to a temporary file in the
// same folder, is checked (short writes, a full disk, a failed flush or close) and is then
// renamed over the final name, so a reader or a killed process sees either the old file or
// the whole new one.
#pragma once

#include <cstddef>
#include <functional>
#include <string>

namespace multiray {

// Writes `n` bytes to `path` atomically. Throws InputError naming the path and the reason.
void write_file_atomically(const std::string& path, const void* data, size_t n);
inline void write_file_atomically(const std::string& path, const std::string& text) {
  write_file_atomically(path, text.data(), text.size());
}

// For writers that insist on a path of their own (e.g. OpenEXR): `write(temp)` writes the
// file at `temp`; it is then checked to exist, synced and renamed to `path`. Throws
// InputError (the temporary file is removed).
void replace_file_atomically(const std::string& path,
                             const std::function<void(const std::string& temp)>& write);

}  // namespace multiray
