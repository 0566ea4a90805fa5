// Bytes on the wire between ranks: a writer that appends plain values and a reader that
// checks every read against the end of the message. Every rank runs the same binary on
// the same kind of machine (one mpirun job), so values travel in the host's byte order.
#pragma once

#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace multiray::remote {

// A message that does not parse: truncated, or a count larger than what follows.
class WireError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class ByteWriter {
 public:
  template <class T>
  void put(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    const auto* p = reinterpret_cast<const uint8_t*>(&v);
    bytes_.insert(bytes_.end(), p, p + sizeof(T));
  }
  void put_string(const std::string& s) {
    put(uint64_t(s.size()));
    bytes_.insert(bytes_.end(), s.begin(), s.end());
  }
  template <class T>
  void put_array(const std::vector<T>& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    put(uint64_t(v.size()));
    const auto* p = reinterpret_cast<const uint8_t*>(v.data());
    bytes_.insert(bytes_.end(), p, p + v.size() * sizeof(T));
  }
  void put_bytes(const uint8_t* p, size_t n) { bytes_.insert(bytes_.end(), p, p + n); }
  std::vector<uint8_t> take() { return std::move(bytes_); }

 private:
  std::vector<uint8_t> bytes_;
};

class ByteReader {
 public:
  explicit ByteReader(const std::vector<uint8_t>& bytes) : bytes_(bytes) {}
  template <class T>
  T get() {
    static_assert(std::is_trivially_copyable_v<T>);
    need(sizeof(T));
    T v;
    std::memcpy(&v, bytes_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  std::string get_string() {
    const uint64_t n = count(1);
    std::string s(reinterpret_cast<const char*>(bytes_.data() + pos_), size_t(n));
    pos_ += size_t(n);
    return s;
  }
  template <class T>
  std::vector<T> get_array() {
    const uint64_t n = count(sizeof(T));
    std::vector<T> v(static_cast<size_t>(n));
    if (n) std::memcpy(v.data(), bytes_.data() + pos_, size_t(n) * sizeof(T));
    pos_ += size_t(n) * sizeof(T);
    return v;
  }
  // The next `n` bytes, in place (valid while the message is).
  const uint8_t* get_bytes(size_t n) {
    need(n);
    const uint8_t* p = bytes_.data() + pos_;
    pos_ += n;
    return p;
  }
  // A count of elements of `size` bytes that the rest of the message can hold.
  uint64_t count(size_t size) {
    const uint64_t n = get<uint64_t>();
    if (size > 0 && n > (bytes_.size() - pos_) / size)
      throw WireError("message truncated: a count of " + std::to_string(n) + " is too large");
    return n;
  }
  bool done() const { return pos_ == bytes_.size(); }

 private:
  void need(size_t n) const {
    if (bytes_.size() - pos_ < n) throw WireError("message truncated");
  }
  const std::vector<uint8_t>& bytes_;
  size_t pos_ = 0;
};

}  // namespace multiray::remote
