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

// Bytes written in order: values copied in (put, put_vector, put_bytes) or memory referenced
// in place (put_view), which must stay as it is until the bytes are used: a checkpoint's
// particle fields go to the file from where they are, without a copy of the state.
class ByteWriter {
 public:
  template <class T>
  void put(const T& value) {
    put_bytes(reinterpret_cast<const char*>(&value), sizeof(T));
  }
  template <class T>
  void put_vector(const std::vector<T>& values) {
    put<uint64_t>(values.size());
    put_bytes(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
  }
  void put_bytes(const char* data, size_t size) {
    if (pieces_.empty() || pieces_.back().view) pieces_.emplace_back();
    pieces_.back().owned.append(data, size);
  }
  void put_bytes(const std::string& bytes) { put_bytes(bytes.data(), bytes.size()); }
  void put_view(const char* data, size_t size) {
    if (size > 0) pieces_.push_back({{}, data, size});
  }
  size_t size() const {
    size_t n = 0;
    for_each_piece([&](const char*, size_t k) { n += k; });
    return n;
  }
  // fn(data, size) for each piece, in order.
  template <class Fn>
  void for_each_piece(Fn&& fn) const {
    for (const Piece& p : pieces_)
      p.view ? fn(p.view, p.size) : fn(p.owned.data(), p.owned.size());
  }
  // All the bytes in one string.
  std::string bytes() const {
    std::string out;
    out.reserve(size());
    for_each_piece([&](const char* data, size_t k) { out.append(data, k); });
    return out;
  }

 private:
  struct Piece {
    std::string owned;
    const char* view = nullptr;  // or memory referenced in place
    size_t size = 0;
  };
  std::vector<Piece> pieces_;
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

// A 64-bit checksum of `total` bytes (8 at a time, multiply-xorshift mixing; not
// cryptographic): it catches truncation, bit flips and torn writes of checkpoints. Fed in
// pieces of any size (add), as if they were one array.
class Checksum64 {
 public:
  explicit Checksum64(size_t total) : h_(0x9e3779b97f4a7c15ull ^ total) {}
  void add(const char* data, size_t size) {
    if (pending_ > 0) {  // complete the word a previous piece began
      const size_t k = std::min(8 - pending_, size);
      std::memcpy(word_ + pending_, data, k);
      pending_ += k, data += k, size -= k;
      if (pending_ < 8) return;
      mix(word_);
      pending_ = 0;
    }
    for (; size >= 8; data += 8, size -= 8) mix(data);
    std::memcpy(word_, data, size);
    pending_ = size;
  }
  uint64_t finish() {
    std::memset(word_ + pending_, 0, 8 - pending_);  // the tail, zero-padded (maybe empty)
    mix(word_);
    h_ *= 0x94d049bb133111ebull;
    return h_ ^ (h_ >> 29);
  }

 private:
  void mix(const char* bytes) {
    uint64_t w;
    std::memcpy(&w, bytes, 8);
    h_ ^= w;
    h_ *= 0xbf58476d1ce4e5b9ull;
    h_ ^= h_ >> 31;
  }
  uint64_t h_;
  char word_[8];
  size_t pending_ = 0;
};

inline uint64_t checksum64(const char* data, size_t size) {
  Checksum64 c(size);
  c.add(data, size);
  return c.finish();
}

// Appends the checksum of `bytes` to it.
inline void append_checksum(std::string* bytes) {
  const uint64_t c = checksum64(bytes->data(), bytes->size());
  bytes->append(reinterpret_cast<const char*>(&c), sizeof(c));
}

// Puts the checksum of what `w` holds so far.
inline void put_checksum(ByteWriter* w) {
  Checksum64 c(w->size());
  w->for_each_piece([&](const char* data, size_t size) { c.add(data, size); });
  w->put<uint64_t>(c.finish());
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
