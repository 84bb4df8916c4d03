#include "tear/driver/command.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

namespace tear {

int fail(std::string why, int code) {
  for (char& c : why)
    if (c == '\n' || c == '\r') c = ' ';
  std::fprintf(stderr, "tear: %s\n", why.c_str());
  return code;
}

std::unique_ptr<ThreadLimit> limit_threads(int threads) {
  return std::make_unique<ThreadLimit>(threads);
}

std::vector<FrameFile> frames_in_range(const std::string& dir, const FrameRange& range) {
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) throw std::runtime_error(dir + ": no such folder");
  std::vector<FrameFile> files;
  for (const FrameFile& f : list_frames(dir))
    if (range.contains(f.frame)) files.push_back(f);
  if (files.empty()) {
    const bool all = range.first == 0 && range.last < 0;
    const std::string text = (range.first > 0 ? std::to_string(range.first) : "") + ":" +
                             (range.last >= 0 ? std::to_string(range.last) : "");
    throw std::runtime_error(dir + ": no frames" + (all ? "" : " in --frames " + text));
  }
  return files;
}

std::string clock_text(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) return "--:--";
  const long s = std::lround(seconds);
  char buf[32];
  if (s >= 3600)
    std::snprintf(buf, sizeof(buf), "%ld:%02ld:%02ld", s / 3600, (s / 60) % 60, s % 60);
  else
    std::snprintf(buf, sizeof(buf), "%ld:%02ld", s / 60, s % 60);
  return buf;
}

}  // namespace tear
