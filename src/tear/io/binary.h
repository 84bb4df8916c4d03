// io/: a minimal binary encoder/decoder for checkpoints: plain values (scalars, fixed-size
// Eigen vectors and matrices) and vectors of them, in host byte order, bounds-checked reads.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace tear {

class ByteWriter {
 public:
  template <class T>
  void put(const T& value) {
    bytes_.append(reinterpret_cast<const char*>(&value), sizeof(T));
  }
  template <class T>
  void put_vector(const std::vector<T>& values) {
    put<uint64_t>(values.size());
    bytes_.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
  }
  std::string& bytes() { return bytes_; }

 private:
  std::string bytes_;
};

// Throws std::runtime_error("truncated ...") when the input ends early.
class ByteReader {
 public:
  // Reads `bytes` (which must outlive the reader) from offset `pos` up to `end` (default: all).
  explicit ByteReader(const std::string& bytes, size_t pos = 0, size_t end = std::string::npos)
      : bytes_(bytes), pos_(pos), end_(std::min(end, bytes.size())) {}
  // A temporary would be gone before the first read (found by AddressSanitizer in a test).
  ByteReader(std::string&& bytes, size_t pos = 0, size_t end = std::string::npos) = delete;
  template <class T>
  T get() {
    T value;
    take(&value, sizeof(T));
    return value;
  }
  // Reads a vector written by ByteWriter::put_vector, of any length.
  template <class T>
  void get_vector(std::vector<T>* values) {
    const uint64_t n = get<uint64_t>();
    if (n > (end_ - pos_) / sizeof(T)) throw std::runtime_error("truncated data");
    values->resize(n);
    take(values->data(), n * sizeof(T));
  }
  // The next `size` bytes, in place (valid while the input lives).
  const char* get_view(size_t size) {
    if (end_ - pos_ < size) throw std::runtime_error("truncated data");
    const char* p = bytes_.data() + pos_;
    pos_ += size;
    return p;
  }
  bool at_end() const { return pos_ == end_; }

 private:
  void take(void* out, size_t size) {
    if (end_ - pos_ < size) throw std::runtime_error("truncated data");
    std::memcpy(out, bytes_.data() + pos_, size);
    pos_ += size;
  }
  const std::string& bytes_;
  size_t pos_, end_;
};

// A 64-bit checksum of `size` bytes (8 at a time, multiply-xorshift mixing; not
// cryptographic): it catches truncation, bit flips and torn writes of checkpoints.
inline uint64_t checksum64(const char* data, size_t size) {
  uint64_t h = 0x9e3779b97f4a7c15ull ^ size;
  const auto mix = [&](uint64_t w) {
    h ^= w;
    h *= 0xbf58476d1ce4e5b9ull;
    h ^= h >> 31;
  };
  size_t i = 0;
  for (; i + 8 <= size; i += 8) {
    uint64_t w;
    std::memcpy(&w, data + i, 8);
    mix(w);
  }
  uint64_t tail = 0;
  std::memcpy(&tail, data + i, size - i);
  mix(tail);
  h *= 0x94d049bb133111ebull;
  return h ^ (h >> 29);
}

// Appends the checksum of `bytes` to it.
inline void append_checksum(std::string* bytes) {
  const uint64_t c = checksum64(bytes->data(), bytes->size());
  bytes->append(reinterpret_cast<const char*>(&c), sizeof(c));
}

// Whether `bytes` ends with the checksum of what precedes it (append_checksum); the payload is
// bytes.size() - 8 long.
inline bool checksum_matches(const std::string& bytes) {
  if (bytes.size() < sizeof(uint64_t)) return false;
  const size_t n = bytes.size() - sizeof(uint64_t);
  uint64_t c;
  std::memcpy(&c, bytes.data() + n, sizeof(c));
  return c == checksum64(bytes.data(), n);
}

}  // namespace tear
