// io/: a minimal binary encoder/decoder for checkpoints: plain values (scalars, fixed-size
// Eigen vectors and matrices) and vectors of them, in host byte order, bounds-checked reads.
#pragma once

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
  // Reads `bytes` (which must outlive the reader) from offset `pos`.
  explicit ByteReader(const std::string& bytes, size_t pos = 0) : bytes_(bytes), pos_(pos) {}
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
    if (n > (bytes_.size() - pos_) / sizeof(T)) throw std::runtime_error("truncated data");
    values->resize(n);
    take(values->data(), n * sizeof(T));
  }
  // The next `size` bytes, in place (valid while the input lives).
  const char* get_view(size_t size) {
    if (bytes_.size() - pos_ < size) throw std::runtime_error("truncated data");
    const char* p = bytes_.data() + pos_;
    pos_ += size;
    return p;
  }
  bool at_end() const { return pos_ == bytes_.size(); }

 private:
  void take(void* out, size_t size) {
    if (bytes_.size() - pos_ < size) throw std::runtime_error("truncated data");
    std::memcpy(out, bytes_.data() + pos_, size);
    pos_ += size;
  }
  const std::string& bytes_;
  size_t pos_;
};

}  // namespace tear
