#include "tear/driver/convert.h"

#include "tear/driver/command.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include <set>

#include "tear/io/atomic_file.h"
#include "tear/io/mesh_frames.h"
#include "tear/io/vtu.h"

namespace tear {

namespace fs = std::filesystem;

namespace {

// A format for the particles' frames or for the mesh parts (cloth, yarn, hair).
bool known_format(const std::string& format) {
  const std::vector<std::string>& m = mesh_part_formats();
  return is_point_format(format) || std::find(m.begin(), m.end(), format) != m.end();
}

std::string unknown_format(const std::string& dir, const std::string& format) {
  std::string meshes;
  for (const std::string& f : mesh_part_formats()) meshes += (meshes.empty() ? "" : ", ") + f;
  return dir + ": unknown format \"" + format + "\" for --to (known: " + point_format_list() +
         " for the particles; " + meshes + " for the cloth, yarn and hair meshes)";
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
  if (!known_format(format)) throw std::runtime_error(unknown_format(dir, format));
  const std::vector<std::string>& mf = mesh_part_formats();
  const bool points = is_point_format(format),
             meshes = std::find(mf.begin(), mf.end(), format) != mf.end();
  ConvertCounts counts;
  std::error_code ec;
  std::set<std::string> parts;  // those written in the format
  for (const FrameFile& f : frames_in_range(dir, range)) {
    const std::string target = frame_path(dir, f.frame, format);
    if (points && fs::exists(target, ec)) {
      ++counts.skipped;
    } else if (points) {
      write_file_atomic(target, encode_points(read_frame(f.path), format));
      ++counts.converted;
    }
    if (!meshes) continue;
    for (const MeshPart& part : read_mesh_parts(dir, f.frame)) {
      parts.insert(part.name);
      const std::string mesh = mesh_part_path(dir, f.frame, part.name, format);
      if (fs::exists(mesh, ec)) {
        ++counts.meshes_skipped;
        continue;
      }
      write_file_atomic(mesh, encode_mesh_part(part, format));
      ++counts.meshes_converted;
    }
  }
  if (!points && parts.empty())
    throw std::runtime_error(dir + ": " + format + " is a format for meshes only, and the run " +
                             "has no cloth, yarn or hair meshes in the frames asked for");
  if (format == "vtu") {
    // Frame times from the run's stats (the frame number stands in where they are missing).
    std::vector<std::string> lines;
    const fs::path stats = fs::path(dir) / "stats.jsonl";
    if (fs::exists(stats, ec)) {
      std::istringstream in(read_file(stats.string()));
      for (std::string line; std::getline(in, line);) lines.push_back(line);
    }
    const std::map<int, double> times = frame_times(lines);
    if (points) counts.pvd_entries = write_frames_pvd(dir, times);
    // DIR/PART.pvd: every frame that has the part in vtu, at its time.
    for (const std::string& part : parts) {
      std::map<int, double> at;
      for (const FrameFile& f : list_frames(dir))
        if (fs::exists(mesh_part_path(dir, f.frame, part, "vtu"), ec))
          at[f.frame] = times.count(f.frame) ? times.at(f.frame) : double(f.frame);
      write_mesh_part_pvd(dir, part, at);
    }
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
  if (!known_format(o.format)) return fail(unknown_format(o.dir, o.format), 2);
  try {
    const auto start = std::chrono::steady_clock::now();
    const ConvertCounts c = convert_frames(o.dir, o.format, range);
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (is_point_format(o.format))
      std::printf("converted %zu frames of %s to %s (%zu already %s) in %.1f s\n", c.converted,
                  o.dir.c_str(), o.format.c_str(), c.skipped, o.format.c_str(), wall);
    if (c.meshes_converted + c.meshes_skipped > 0 || !is_point_format(o.format))
      std::printf("converted %zu meshes of %s to %s (%zu already %s) in %.1f s\n",
                  c.meshes_converted, o.dir.c_str(), o.format.c_str(), c.meshes_skipped,
                  o.format.c_str(), wall);
    if (o.format == "vtu")
      std::printf("wrote %s (%zu frames)\n", (fs::path(o.dir) / "frames.pvd").string().c_str(),
                  c.pvd_entries);
    return 0;
  } catch (const std::exception& e) {
    return fail(e.what());
  }
}

}  // namespace tear
