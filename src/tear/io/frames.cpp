#include "tear/io/frames.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <stdexcept>

#include "tear/io/atomic_file.h"
#include "tear/io/bgeo.h"
#include "tear/io/ply.h"
#include "tear/io/vtu.h"

namespace tear {

namespace fs = std::filesystem;

const std::vector<std::string> &point_formats() {
  static const std::vector<std::string> kFormats{"ply", "bgeo", "vtu"};
  return kFormats;
}

std::string point_format_list(const std::string &separator) {
  std::string out;
  for (const std::string &f : point_formats()) out += (out.empty() ? "" : separator) + f;
  return out;
}

bool is_point_format(const std::string &format) {
  const std::vector<std::string> &formats = point_formats();
  return std::find(formats.begin(), formats.end(), format) != formats.end();
}

std::string frame_path(const std::string &dir, int frame, const std::string &format) {
  char name[32];
  std::snprintf(name, sizeof(name), "%05d.", frame);
  return (fs::path(dir) / "frames" / (name + format)).string();
}

namespace {

// The frames of DIR in any point format (`only` null) or in `*only`.
std::vector<FrameFile> scan_frames(const std::string &dir, const std::string *only) {
  const fs::path folder = fs::path(dir) / "frames";
  std::error_code ec;
  if (!fs::is_directory(folder, ec))
    throw std::runtime_error(dir + ": no frames/ folder (is it the output folder of tear run?)");
  const std::vector<std::string> &formats = point_formats();
  std::map<int, FrameFile> best;
  for (const fs::directory_entry &e : fs::directory_iterator(folder)) {
    if (!e.is_regular_file()) continue;
    const std::string stem = e.path().stem().string();
    const std::string ext = e.path().extension().string();
    if (stem.size() < 5 || ext.size() < 2 ||
        !std::all_of(stem.begin(), stem.end(), [](char c) { return c >= '0' && c <= '9'; }))
      continue;
    const auto rank = std::find(formats.begin(), formats.end(), ext.substr(1));
    if (rank == formats.end() || (only && *rank != *only)) continue;
    const int frame = std::stoi(stem);
    auto it = best.find(frame);
    if (it != best.end() && std::find(formats.begin(), formats.end(), it->second.format) < rank)
      continue;
    best[frame] = FrameFile{frame, e.path().string(), *rank};
  }
  std::vector<FrameFile> out;
  for (auto &[frame, file] : best) out.push_back(file);
  return out;
}

}  // namespace

std::vector<FrameFile> list_frames(const std::string &dir) { return scan_frames(dir, nullptr); }

std::vector<FrameFile> list_frames(const std::string &dir, const std::string &format) {
  return scan_frames(dir, &format);
}

FrameRange parse_frame_range(const std::string &text) {
  auto bad = [&]() {
    return std::runtime_error("--frames \"" + text +
                              "\": expected A:B, A:, :B or A (frame numbers >= 0, A <= B)");
  };
  auto number = [&](const std::string &s, int fallback) {
    if (s.empty()) return fallback;
    if (s.size() > 9 ||
        !std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; }))
      throw bad();
    return std::stoi(s);
  };
  FrameRange r;
  const size_t colon = text.find(':');
  if (colon == std::string::npos) {
    if (text.empty()) return r;
    r.first = r.last = number(text, 0);
    return r;
  }
  if (text.find(':', colon + 1) != std::string::npos) throw bad();
  r.first = number(text.substr(0, colon), 0);
  r.last = number(text.substr(colon + 1), -1);
  if (r.last >= 0 && r.last < r.first) throw bad();
  return r;
}

PointTable read_frame(const std::string &path) {
  const std::string ext = fs::path(path).extension().string();
  const std::string format = ext.empty() ? "" : ext.substr(1);
  if (!is_point_format(format))
    throw std::runtime_error(path + ": unknown point format \"" + ext + "\" (expected ." +
                             point_format_list(", .") + ")");
  const std::string bytes = read_file(path);  // its errors name the path
  try {
    if (format == "bgeo") return decode_bgeo(bytes);
    if (format == "vtu") return decode_vtu(bytes);
    return decode_ply(bytes);
  } catch (const std::exception &e) {
    throw std::runtime_error(path + ": " + e.what());
  }
}

std::string encode_points(const PointTable &table, const std::string &format) {
  if (format == "bgeo") return encode_bgeo(table);
  if (format == "vtu") return encode_vtu(table);
  std::string out;
  encode_points(rows_of(table), format, &out);
  return out;
}

void encode_points(const PointRows &rows, const std::string &format, std::string *out,
                   PointTable *scratch) {
  if (format == "ply") return encode_ply(rows, out);
  if (format == "bgeo" || format == "vtu") {
    PointTable own;
    PointTable &table = scratch ? *scratch : own;
    fill_table(rows, &table);
    *out = encode_points(table, format);
    return;
  }
  throw std::runtime_error("unknown point format \"" + format + "\" (expected one of: " +
                           point_format_list() + ")");
}

}  // namespace tear
