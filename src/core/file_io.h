// Output files that are never half-written: every write goes to a temporary file in the
// same folder, is checked (short writes, a full disk, a failed flush or close) and is then
// renamed over the final name, so a reader or a killed process sees either the old file or
// the whole new one.
#pragma once

#include <cstddef>
#include <functional>
#include <string>

namespace multiray {

// Refuses (InputError naming `option` and `path`) an output path that exists and is not a
// regular file (after links): a FIFO, a device such as /dev/null, a folder or a socket.
// Outputs are renamed into place, so writing one would replace the special file itself
// (as root, /dev/null). A link to a regular file is fine: the link is replaced, not its
// target. Called by every writer below and early, before a run starts, for each output
// option.
void check_output_file(const std::string& path, const std::string& option);

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
