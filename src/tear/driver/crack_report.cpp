#include "tear/driver/crack_report.h"

#include "tear/damage/crack_metrics.h"
#include "tear/driver/command.h"
#include "tear/io/frames.h"
#include "tear/scene/scene.h"
#include "tear/surface/mesher.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>

namespace tear {

namespace fs = std::filesystem;

int crack_report(const CrackReportOptions& o) {
  FrameRange range;
  try {
    range = parse_frame_range(o.frames);
  } catch (const std::exception& e) {
    return fail(e.what(), 2);
  }
  if (!(o.threshold >= 0 && o.threshold < 1))
    return fail("--threshold " + std::to_string(o.threshold) + ": must be in [0, 1)");
  try {
    // Rest positions: frame 0 (rows are in particle id order in every frame).
    const std::vector<FrameFile> all = frames_in_range(o.dir, FrameRange{});
    if (all.front().frame != 0)
      return fail(o.dir + ": no frame 0 (the rest positions); the crack figures need it");
    const PointTable rest_table = read_frame(all.front().path);
    const std::vector<Vec3d> rest = positions(rest_table);
    int dim = 3;
    double spacing = o.spacing;
    const std::string scene_path = (fs::path(o.dir) / "scene.json").string();
    if (fs::exists(scene_path)) {
      const Scene s = load_scene(scene_path);
      dim = s.dim;
      if (spacing == 0) spacing = particle_spacing(s);
    } else {
      dim = 2;
      for (const Vec3d& p : rest) dim = p[2] != 0 ? 3 : dim;
      if (spacing == 0) spacing = estimate_spacing(rest_table);
      if (!(spacing > 0))
        return fail(all.front().path + ": cannot estimate the particle spacing; give --spacing");
    }
    if (!o.json)
      std::printf("%6s %9s %9s  %-22s %9s %9s\n", "frame", "cracked", "fraction",
                  dim == 2 ? "crack angle (deg)" : "crack normal", "width", "spacings");
    for (const FrameFile& f : frames_in_range(o.dir, range)) {
      const PointTable t = read_frame(f.path);
      if (t.count != rest.size())
        return fail(f.path + ": " + std::to_string(t.count) + " particles, frame 0 has " +
                    std::to_string(rest.size()));
      if (!t.has("damage")) return fail(f.path + ": no damage column");
      const CrackFigures c = measure_cracks(dim, rest, t.column("damage"), spacing, o.threshold);
      if (o.json) {
        nlohmann::json j = {{"frame", f.frame},
                            {"cracked", c.cracked},
                            {"fraction", c.fraction},
                            {"width", c.width},
                            {"width_spacings", c.width_spacings},
                            {"normal", {c.normal[0], c.normal[1], c.normal[2]}}};
        if (dim == 2) j["angle_degrees"] = c.angle_degrees;
        std::printf("%s\n", j.dump().c_str());
        continue;
      }
      char dir[64] = "-";
      if (c.cracked >= 3) {
        if (dim == 2)
          std::snprintf(dir, sizeof(dir), "%.1f", c.angle_degrees);
        else
          std::snprintf(dir, sizeof(dir), "(%.3f, %.3f, %.3f)", c.normal[0], c.normal[1],
                        c.normal[2]);
      }
      std::printf("%6d %9zu %9.4f  %-22s %9.4g %9.2f\n", f.frame, c.cracked, c.fraction, dir,
                  c.width, c.width_spacings);
    }
    return 0;
  } catch (const std::exception& e) {
    return fail(e.what());
  }
}

}  // namespace tear
