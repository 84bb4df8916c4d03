// io/: numbers in a file's fixed byte order (little-endian PLY and VTU, big-endian BGEO)
// whatever the host's; on a host of the same order these compile to plain loads and stores.
#pragma once

#include <algorithm>
#include <cstring>
#include <string>

namespace tear {

constexpr bool kHostLittleEndian = __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__;

namespace endian_detail {

// Stores and loads `T` with its bytes in little-endian (`Little`) or big-endian order.
template <bool Little, class T>
void store(char* p, T value) {
  char b[sizeof(T)];
  std::memcpy(b, &value, sizeof(T));
  if constexpr (Little != kHostLittleEndian) std::reverse(b, b + sizeof(T));
  std::memcpy(p, b, sizeof(T));
}

template <bool Little, class T>
T load(const char* p) {
  char b[sizeof(T)];
  std::memcpy(b, p, sizeof(T));
  if constexpr (Little != kHostLittleEndian) std::reverse(b, b + sizeof(T));
  T value;
  std::memcpy(&value, b, sizeof(T));
  return value;
}

}  // namespace endian_detail

template <class T>
void store_le(char* p, T value) {
  endian_detail::store<true>(p, value);
}
template <class T>
void store_be(char* p, T value) {
  endian_detail::store<false>(p, value);
}
template <class T>
T load_le(const char* p) {
  return endian_detail::load<true, T>(p);
}
template <class T>
T load_be(const char* p) {
  return endian_detail::load<false, T>(p);
}
template <class T>
void append_le(std::string* out, T value) {
  char b[sizeof(T)];
  store_le(b, value);
  out->append(b, sizeof(T));
}
template <class T>
void append_be(std::string* out, T value) {
  char b[sizeof(T)];
  store_be(b, value);
  out->append(b, sizeof(T));
}

}  // namespace tear
