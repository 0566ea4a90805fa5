// The text side of reading NRRD files, before Teem sees them (load_nrrd.cpp). Teem opens a
// detached header's data file by itself (even to read only the header), which would block
// forever on a FIFO; so the header is split here, the "data file:" line taken out and the
// named file checked and read through core/scene_files.h, and Teem only ever reads from
// memory. Private to src/volume.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

namespace multiray::volume_detail {

struct NrrdHeaderParts {
  std::string header;  // the header's lines without "data file:", each ending in '\n'
  // The same without "line skip:" and "byte skip:" lines: Teem skips lines and bytes even
  // when asked for the header only, so that parse must not see them.
  std::string header_no_skips;
  uint64_t line_skip = 0;  // lines before the data (after the blank line, or of the file)
  int64_t byte_skip = 0;   // then bytes; -1: the data are the file's last bytes
  std::string data_file;   // the one data file named, as written; empty if data is attached
  size_t data_offset = 0;  // attached data: where it starts in the file (after the blank line)
  bool has_blank_line = false;  // whether the header ends with an empty line
};

// Splits the text of a NRRD file. Throws InputError "<path>: <problem>" for a file that
// does not start with "NRRD000", more than one "data file:" line, lists / numbered
// series of data files, or a line or byte skip that is not a whole number (byte skip
// may be -1). A line is taken as "data file:" the way Teem would take it
// (field names case-insensitive), and also in spellings Teem would refuse (extra spaces),
// so Teem never sees a data file it would open.
NrrdHeaderParts split_nrrd_header(const std::string& path, const std::string& text);

// A read-only FILE* over the concatenation of `parts` (fopencookie), seekable, so Teem can
// read a header and its data from memory. The parts must outlive it.
class SpanFile {
 public:
  explicit SpanFile(std::vector<std::string_view> parts);
  ~SpanFile();
  SpanFile(const SpanFile&) = delete;
  SpanFile& operator=(const SpanFile&) = delete;
  FILE* get() const { return file_; }

 private:
  static ssize_t read(void* cookie, char* buf, size_t n);
  static int seek(void* cookie, off64_t* offset, int whence);

  std::vector<std::string_view> parts_;
  size_t size_ = 0, pos_ = 0;  // total bytes, read position
  FILE* file_ = nullptr;
};

}  // namespace multiray::volume_detail
