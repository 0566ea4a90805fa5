// gzip-encoded NRRD data, decoded here with zlib rather than by Teem: Teem's reader stops
// once it has the bytes the header asks for, so it never reaches zlib's check of the
// stream's CRC and length (8 corrupted bytes rendered silently wrong) and never sees data
// that decode to more than the header describes. Here the whole stream is decoded and
// every status checked, and the voxels' buffer is allocated only once the data's size
// shows they can hold them (deflate expands at most 1032-fold): a 100-byte file claiming
// gigabytes of voxels is refused before anything is allocated.
#include <zlib.h>

#include <algorithm>
#include <climits>
#include <new>

#include "core/scene_files.h"
#include "volume/volume_input.h"

namespace multiray::volume_detail {

using detail::fail;

namespace {

// Deflate's largest expansion: 258 bytes from 2 bits, about 1032 output bytes per input
// byte (zlib's technical notes); gzip framing only lowers it.
constexpr uint64_t kMaxInflateRatio = 1032;
constexpr size_t kChunk = size_t(1) << 18;

std::string bytes_text(uint64_t n) { return std::to_string(n) + (n == 1 ? " byte" : " bytes"); }

// Decodes gzip data chunk by chunk, every zlib status checked. Throws InputError
// "<path>: <what>: <problem>" for corrupt data (zlib's CRC and length checks included),
// a stream cut short, or bytes after the last member that start no other member.
class GzipReader {
 public:
  GzipReader(const std::string& path, const std::string& what, std::string_view gz)
      : path_(path), what_(what), gz_(gz), chunk_(kChunk, '\0') {
    if (inflateInit2(&z_, 16 + MAX_WBITS) != Z_OK) throw std::bad_alloc();  // gzip wrapper
  }
  ~GzipReader() { inflateEnd(&z_); }
  GzipReader(const GzipReader&) = delete;
  GzipReader& operator=(const GzipReader&) = delete;

  // The next decoded bytes (valid until the next call); empty once the data have ended.
  std::string_view next() {
    while (!done_) {
      if (z_.avail_in == 0 && fed_ < gz_.size()) {  // zlib takes at most 4 GiB at a time
        const size_t n = std::min<size_t>(gz_.size() - fed_, UINT_MAX);
        z_.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(gz_.data() + fed_));
        z_.avail_in = unsigned(n);
        fed_ += n;
      }
      z_.next_out = reinterpret_cast<Bytef*>(chunk_.data());
      z_.avail_out = unsigned(chunk_.size());
      const int ret = inflate(&z_, Z_NO_FLUSH);
      const size_t got = chunk_.size() - z_.avail_out;
      const uint64_t left = z_.avail_in + (gz_.size() - fed_);  // input not yet decoded
      if (ret == Z_STREAM_END) {
        // Another gzip member (as `cat a.gz b.gz` makes) continues the data.
        const bool member = z_.avail_in >= 2 && z_.next_in[0] == 0x1f && z_.next_in[1] == 0x8b;
        if (left == 0)
          done_ = true;
        else if (!member || inflateReset(&z_) != Z_OK)
          fail(path_, what_ + " has " + bytes_text(left) + " after the end of its gzip data");
      } else if (ret == Z_MEM_ERROR) {
        throw std::bad_alloc();
      } else if (ret == Z_BUF_ERROR && left == 0) {
        fail(path_, what_ + ": the gzip data end before their stream does (truncated)");
      } else if (ret != Z_OK && ret != Z_BUF_ERROR) {
        fail(path_, what_ + ": the gzip data are corrupt (zlib: " +
                        std::string(z_.msg ? z_.msg : zError(ret)) + ")");
      }
      if (got > 0) return std::string_view(chunk_.data(), got);
    }
    return {};
  }

 private:
  const std::string& path_;
  const std::string& what_;
  std::string_view gz_;
  std::string chunk_;
  z_stream z_{};
  size_t fed_ = 0;  // input bytes handed to zlib so far
  bool done_ = false;
};

}  // namespace

uint64_t max_gunzip_bytes(uint64_t gzip_bytes) { return gzip_bytes * kMaxInflateRatio; }

std::string gunzip_voxels(const std::string& path, const std::string& what, std::string_view gz,
                          int64_t byte_skip, uint64_t need, const std::string& grid) {
  const uint64_t skip = byte_skip > 0 ? uint64_t(byte_skip) : 0;
  const uint64_t want = skip + need;  // decoded bytes the header describes
  if (want > max_gunzip_bytes(gz.size()))
    fail(path, what + " is too short for " + grid + ": " + bytes_text(gz.size()) +
                   " of gzip data decode to at most " + bytes_text(max_gunzip_bytes(gz.size())) +
                   ", " + std::to_string(want) + " are needed");
  // Byte skip -1: the voxels are the last `need` decoded bytes; as for raw data files,
  // at most data_file_slack() bytes may come before them.
  const uint64_t keep = byte_skip == -1 ? need + data_file_slack(need) : want;
  // Beyond `keep`, bytes are counted, not kept, so that data a little too long get their
  // exact length (or zlib's verdict that they are corrupt); up to a bound, because a
  // small file may decode to gigabytes of zeros.
  const uint64_t give_up = keep + std::max<uint64_t>(keep, uint64_t(64) << 20);
  std::string out;
  out.reserve(size_t(want));
  uint64_t total = 0;
  GzipReader reader(path, what, gz);
  for (std::string_view got; !(got = reader.next()).empty();) {
    total += got.size();
    if (out.size() < keep) out.append(got.substr(0, size_t(keep - out.size())));
    if (total > give_up)
      fail(path, what + " (gzip) is too long: it decodes to more than " + bytes_text(give_up) +
                     ", " + bytes_text(want) + " are described");
  }
  const std::string decoded = what + " (gzip, decoded)";
  if (byte_skip == -1) {
    if (total > keep)
      fail(path, decoded + " holds " + bytes_text(total) + ": with byte skip -1, at most " +
                     bytes_text(keep - need) + " may precede the " + bytes_text(need) +
                     " of voxel data");
    check_data_size(path, decoded, std::min(total, need), need, grid);
    out.erase(0, out.size() - size_t(need));
  } else {
    check_data_size(path, decoded, total > skip ? total - skip : 0, need, grid);
    out.erase(0, size_t(skip));
  }
  return out;
}

}  // namespace multiray::volume_detail
