#include "tear/exec/memory.h"

#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <stdexcept>

#include <unistd.h>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace tear {

void advise_huge_pages(const void* p, size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr uintptr_t kHuge = uintptr_t(2) << 20;
  if (bytes < 2 * kHuge) return;
  const uintptr_t begin = (reinterpret_cast<uintptr_t>(p) + kHuge - 1) & ~(kHuge - 1);
  const uintptr_t end = (reinterpret_cast<uintptr_t>(p) + bytes) & ~(kHuge - 1);
  // Advice only: where the kernel refuses (THP off, an old kernel) pages stay 4 KiB.
  if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
#else
  (void)p, (void)bytes;
#endif
}

double physical_memory_bytes() {
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
  return pages > 0 && page > 0 ? double(pages) * double(page) : 0;
}

std::string size_text(double bytes) {
  const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB"};
  int u = 0;
  while (bytes >= 1024 && u < 4) bytes /= 1024, ++u;
  char buf[32];
  std::snprintf(buf, sizeof(buf), u == 0 || bytes >= 100 ? "%.0f %s" : "%.1f %s", bytes, units[u]);
  return buf;
}

double parse_size(const std::string& text) {
  size_t used = 0;
  double value = 0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    throw std::invalid_argument("'" + text + "' is not a size (e.g. 16G, 512M, 0)");
  }
  std::string unit;
  for (size_t i = used; i < text.size(); ++i)
    unit += char(std::toupper(static_cast<unsigned char>(text[i])));
  const char* units[] = {"", "K", "M", "G", "T"};
  double scale = -1;
  for (int k = 0; k < 5; ++k) {
    const std::string u = units[k];
    if (unit == u || (k > 0 && (unit == u + "B" || unit == u + "IB")) || (k == 0 && unit == "B"))
      scale = std::pow(1024.0, k);
  }
  if (scale < 0)
    throw std::invalid_argument("'" + text + "': unknown unit '" + text.substr(used) +
                                "' (K, M, G or T)");
  if (!std::isfinite(value) || value < 0)
    throw std::invalid_argument("'" + text + "': a size must be a finite number >= 0");
  return value * scale;
}

}  // namespace tear
