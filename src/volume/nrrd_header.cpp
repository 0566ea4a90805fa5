#include "volume/nrrd_header.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstring>
#include <new>

#include "core/scene_files.h"

namespace multiray::volume_detail {

using detail::fail;

namespace {

// The field name of a header line in lower case without spaces ("data file", "Data File"
// and "datafile" all give "datafile") and its value, or "" for comments and key/value
// ":=" lines (Teem reads those as key/value pairs and never acts on them).
std::string field_name(std::string_view line, std::string_view* value) {
  const size_t colon = line.find(':');
  if (line.empty() || line.front() == '#' || colon == std::string_view::npos ||
      line.substr(colon, 2) == ":=")
    return "";
  std::string name;
  for (char c : line.substr(0, colon))
    if (c != ' ' && c != '\t') name.push_back(char(std::tolower((unsigned char)c)));
  *value = line.substr(colon + 1);
  while (!value->empty() && (value->front() == ' ' || value->front() == '\t'))
    value->remove_prefix(1);
  while (!value->empty() && (value->back() == ' ' || value->back() == '\t'))
    value->remove_suffix(1);
  return name;
}

// A skip count: digits only (or exactly "-1" where `minus_one` is allowed), at most 2^40.
int64_t parse_skip(const std::string& path, std::string_view value, const char* field,
                   bool minus_one) {
  if (minus_one && value == "-1") return -1;
  int64_t n = 0;
  const bool digits = !value.empty() && value.size() <= 13 &&
                      value.find_first_not_of("0123456789") == std::string_view::npos;
  if (digits) std::from_chars(value.data(), value.data() + value.size(), n);
  if (!digits || n > (int64_t(1) << 40))
    fail(path, std::string(field) + " '" + std::string(value) +
                   "' must be a whole number in 0..2^40" + (minus_one ? " or -1" : ""));
  return n;
}

// Refuses the forms that name several files: "LIST [dim]", "SKIPLIST ..." and the
// numbered "<format %d> <min> <max> <step> [<dim>]".
void check_single_file(const std::string& path, std::string_view value) {
  if (value.empty()) fail(path, "the 'data file:' line names no file");
  const size_t sp = value.find_first_of(" \t");
  const std::string_view first = value.substr(0, sp);
  if (first == "LIST" || first == "SKIPLIST")
    fail(path, "lists of data files are not supported (one data file per volume)");
  if (sp != std::string_view::npos && first.find('%') != std::string_view::npos)
    fail(path, "numbered series of data files are not supported (one data file per volume)");
}

}  // namespace

NrrdHeaderParts split_nrrd_header(const std::string& path, const std::string& text) {
  if (text.compare(0, 7, "NRRD000") != 0)
    fail(path, "not a NRRD file (it does not start with the NRRD000N magic)");
  NrrdHeaderParts parts;
  bool seen_data_file = false;
  size_t pos = 0;
  while (pos < text.size()) {
    const size_t eol = text.find('\n', pos);
    const size_t next = eol == std::string::npos ? text.size() : eol + 1;
    std::string_view line(text.data() + pos, next - pos);
    if (!line.empty() && line.back() == '\n') line.remove_suffix(1);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    pos = next;
    if (line.empty()) {
      parts.has_blank_line = true;
      break;
    }
    std::string_view value;
    const std::string field = field_name(line, &value);
    if (field == "datafile") {
      if (seen_data_file) fail(path, "more than one 'data file:' line");
      seen_data_file = true;
      check_single_file(path, value);
      parts.data_file = std::string(value);
      continue;
    }
    parts.header.append(line).push_back('\n');
    if (field == "lineskip")
      parts.line_skip = uint64_t(parse_skip(path, value, "line skip", false));
    else if (field == "byteskip")
      parts.byte_skip = parse_skip(path, value, "byte skip", true);
    else
      parts.header_no_skips.append(line).push_back('\n');
  }
  parts.data_offset = pos;
  return parts;
}

SpanFile::SpanFile(std::vector<std::string_view> parts) : parts_(std::move(parts)) {
  for (std::string_view p : parts_) size_ += p.size();
  const cookie_io_functions_t io{&SpanFile::read, nullptr, &SpanFile::seek, nullptr};
  file_ = fopencookie(this, "r", io);
  if (!file_) throw std::bad_alloc();
}

SpanFile::~SpanFile() {
  if (file_) std::fclose(file_);
}

ssize_t SpanFile::read(void* cookie, char* buf, size_t n) {
  auto* f = static_cast<SpanFile*>(cookie);
  size_t got = 0, start = 0;  // start: offset of the current part in the whole
  for (std::string_view p : f->parts_) {
    if (got == n) break;
    const size_t end = start + p.size();
    if (f->pos_ < end) {
      const size_t k = std::min(n - got, end - f->pos_);
      std::memcpy(buf + got, p.data() + (f->pos_ - start), k);
      got += k;
      f->pos_ += k;
    }
    start = end;
  }
  return ssize_t(got);
}

int SpanFile::seek(void* cookie, off64_t* offset, int whence) {
  auto* f = static_cast<SpanFile*>(cookie);
  const off64_t base = whence == SEEK_SET   ? 0
                       : whence == SEEK_CUR ? off64_t(f->pos_)
                                            : off64_t(f->size_);
  const off64_t to = base + *offset;
  if (to < 0 || to > off64_t(f->size_)) return -1;
  f->pos_ = size_t(to);
  *offset = to;
  return 0;
}

}  // namespace multiray::volume_detail
