#include "tear/driver/convert.h"

#include "tear/driver/command.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "tear/io/atomic_file.h"
#include "tear/io/vtu.h"

namespace tear {

namespace fs = std::filesystem;

namespace {

std::string unknown_format(const std::string& dir, const std::string& format) {
  return dir + ": unknown format \"" + format + "\" for --to (known: " + point_format_list() + ")";
}

}  // namespace

std::map<int, double> frame_times(const std::vector<std::string>& stats_lines) {
  std::map<int, double> times;
  for (const std::string& line : stats_lines) {
    const nlohmann::json j = nlohmann::json::parse(line, nullptr, false);
    if (j.is_object() && j.contains("frame") && j["frame"].is_number_integer() &&
        j.contains("time") && j["time"].is_number())
      times[j["frame"].get<int>()] = j["time"].get<double>();
  }
  return times;
}

ConvertCounts convert_frames(const std::string& dir, const std::string& format,
                             const FrameRange& range) {
  if (!is_point_format(format)) throw std::runtime_error(unknown_format(dir, format));
  ConvertCounts counts;
  std::error_code ec;
  for (const FrameFile& f : frames_in_range(dir, range)) {
    const std::string target = frame_path(dir, f.frame, format);
    if (fs::exists(target, ec)) {
      ++counts.skipped;
      continue;
    }
    write_file_atomic(target, encode_points(read_frame(f.path), format));
    ++counts.converted;
  }
  if (format == "vtu") {
    // Frame times from the run's stats (the frame number stands in where they are missing).
    std::vector<std::string> lines;
    const fs::path stats = fs::path(dir) / "stats.jsonl";
    if (fs::exists(stats, ec)) {
      std::istringstream in(read_file(stats.string()));
      for (std::string line; std::getline(in, line);) lines.push_back(line);
    }
    counts.pvd_entries = write_frames_pvd(dir, frame_times(lines));
  }
  return counts;
}

int convert_run(const ConvertOptions& o) {
  FrameRange range;
  try {
    range = parse_frame_range(o.frames);
  } catch (const std::exception& e) {
    return fail(e.what(), 2);
  }
  if (!is_point_format(o.format)) return fail(unknown_format(o.dir, o.format), 2);
  try {
    const auto start = std::chrono::steady_clock::now();
    const ConvertCounts c = convert_frames(o.dir, o.format, range);
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("converted %zu frames of %s to %s (%zu already %s) in %.1f s\n", c.converted,
                o.dir.c_str(), o.format.c_str(), c.skipped, o.format.c_str(), wall);
    if (o.format == "vtu")
      std::printf("wrote %s (%zu frames)\n", (fs::path(o.dir) / "frames.pvd").string().c_str(),
                  c.pvd_entries);
    return 0;
  } catch (const std::exception& e) {
    return fail(e.what());
  }
}

}  // namespace tear
