// exec/: large arrays and the machine's memory. The first touch of a fresh page costs a page
// fault; with 4 KiB pages a 100 MiB particle field takes 25,600 of them, which dominate setting
// up a run, writing a checkpoint or a frame (measured: a 141 MiB checkpoint buffer took 0.43 s
// to fill, 0.24 s with huge pages). Large arrays are therefore reserved with reserve_large,
// which asks Linux for transparent huge pages (2 MiB, one fault each) where the system allows
// them (`madvise` or `always` in /sys/kernel/mm/transparent_hugepage/enabled); elsewhere it is
// a plain reserve. Values and results are unaffected.
#pragma once

#include <algorithm>
#include <cstddef>
#include <string>

namespace tear {

// Advise the kernel to back the whole 2 MiB pages inside [p, p + bytes) with huge pages
// (no-op for small ranges and on systems without madvise(MADV_HUGEPAGE)).
void advise_huge_pages(const void* p, size_t bytes);

// Room for n elements in a std::vector or std::string without touching it; when it grows
// (to at least twice its capacity, so that repeated calls stay amortised), the new storage is
// advised as above before anything is written to it.
template <class V>
void reserve_large(V* v, size_t n) {
  if (n <= v->capacity()) return;
  v->reserve(std::max(n, 2 * v->capacity()));
  advise_huge_pages(v->data(), v->capacity() * sizeof(typename V::value_type));
}

// Bytes of physical memory of this machine (0 if unknown).
double physical_memory_bytes();

// "812 KiB", "3.4 MiB": sizes for people.
std::string size_text(double bytes);

// A size as people write it: "2G", "512M", "1.5GiB", "800k", "1000000" (bytes; K, M, G, T are
// powers of 1024, with or without "B" or "iB", any case). Throws std::invalid_argument with
// the reason for anything else, a negative or a non-finite size.
double parse_size(const std::string& text);

}  // namespace tear
