#include "tear/driver/mesh_frames.h"

#include "tear/driver/command.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <stdexcept>

#include "tear/io/atomic_file.h"
#include "tear/io/frames.h"
#include "tear/io/mesh_frames.h"
#include "tear/io/mesh_io.h"
#include "tear/scene/scene.h"
#include "tear/surface/mesher.h"

namespace tear {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

// DIR/meshes/NNNNN.FORMAT, or DIR/meshes/NNNNN.PART.FORMAT for a codimensional part.
std::string mesh_path(const std::string& dir, int frame, const std::string& format,
                      const std::string& part = "") {
  char name[32];
  std::snprintf(name, sizeof(name), "%05d.", frame);
  return (fs::path(dir) / "meshes" / (name + (part.empty() ? "" : part + ".") + format)).string();
}

double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

}  // namespace

int mesh_frames(const MeshFramesOptions& o) {
  FrameRange range;
  try {
    range = parse_frame_range(o.frames);
  } catch (const std::exception& e) {
    return fail(e.what(), 2);
  }
  MeshOptions mesh_options;
  mesh_options.spacing = o.spacing;
  mesh_options.radius = o.radius;
  mesh_options.voxel = o.voxel;
  mesh_options.smooth = o.smooth;
  mesh_options.damage_threshold = o.damage_threshold;
  try {
    check_mesh_options(mesh_options);
  } catch (const std::exception& e) {
    return fail(e.what());
  }
  if (o.formats.empty()) return fail("--format: give obj, ply or both");
  for (const std::string& f : o.formats)
    if (f != "obj" && f != "ply") return fail("--format " + f + ": must be obj or ply");
  try {
    const auto limit = limit_threads(o.threads);
    const Clock::time_point start = Clock::now();
    const std::vector<FrameFile> files = frames_in_range(o.dir, range);
    // One spacing for every frame, that of the particles as sampled, so that stretching does
    // not make later surfaces fatter: from the run's scene (exact for every sampling), else
    // from its first frame (the nearest-neighbour estimate is about 0.65 of the spacing for
    // stratified-random samples).
    if (mesh_options.spacing == 0) {
      const std::string scene_path = (fs::path(o.dir) / "scene.json").string();
      std::string source;
      if (fs::exists(scene_path)) {
        mesh_options.spacing = particle_spacing(load_scene(scene_path));
        source = "dx / ppc^(1/dim) in " + scene_path;
      } else {
        mesh_options.spacing = estimate_spacing(read_frame(files.front().path));
        source = "median nearest-neighbour distance in frame " + std::to_string(files.front().frame);
        if (!(mesh_options.spacing > 0))
          return fail(files.front().path + ": cannot estimate the particle spacing (fewer than " +
                      "two distinct points); give --spacing");
      }
      if (!o.quiet) std::fprintf(stderr, "spacing %g (%s)\n", mesh_options.spacing, source.c_str());
    }
    make_directories((fs::path(o.dir) / "meshes").string());
    const bool tty = ::isatty(STDERR_FILENO) != 0;
    size_t triangles = 0, parts = 0;
    for (size_t i = 0; i < files.size(); ++i) {
      const Clock::time_point frame_start = Clock::now();
      TriMesh mesh;
      // Cloth, yarn and hair are meshes already: written as they are, beside the solids'.
      const std::vector<MeshPart> codim = read_mesh_parts(o.dir, files[i].frame);
      bool solids = true;
      try {
        const PointTable frame = read_frame(files[i].path);
        solids = frame.count > 0 || codim.empty();
        if (solids) mesh = mesh_particles(frame, mesh_options);
      } catch (const std::exception& e) {
        // read_frame names the file itself; the mesher does not.
        const std::string why = e.what();
        return fail(why.find(files[i].path) == std::string::npos ? files[i].path + ": " + why
                                                                 : why);
      }
      for (const std::string& format : o.formats) {
        if (solids)
          write_file_atomic(mesh_path(o.dir, files[i].frame, format),
                            format == "obj" ? encode_obj(mesh) : encode_mesh_ply(mesh));
        for (const MeshPart& part : codim)
          write_file_atomic(mesh_path(o.dir, files[i].frame, format, part.name),
                            encode_mesh_part(part, format));
      }
      parts += codim.size();
      triangles += mesh.triangles.size();
      if (!o.quiet) {
        std::fprintf(stderr, "%smesh %zu/%zu  frame %d  %zu triangles  %.2f s%s", tty ? "\r" : "",
                     i + 1, files.size(), files[i].frame, mesh.triangles.size(),
                     seconds_since(frame_start), tty ? "\033[K" : "\n");
        if (tty && i + 1 == files.size()) std::fprintf(stderr, "\n");
        std::fflush(stderr);
      }
    }
    std::string written;
    for (const std::string& format : o.formats) written += (written.empty() ? "" : ", ") + format;
    const std::string also =
        parts > 0 ? " and " + std::to_string(parts) + " cloth, yarn and hair meshes" : "";
    std::printf("meshed %zu frames (%zu triangles%s, %s) to %s in %.1f s\n", files.size(),
                triangles, also.c_str(), written.c_str(),
                (fs::path(o.dir) / "meshes").string().c_str(), seconds_since(start));
    return 0;
  } catch (const std::exception& e) {
    return fail(e.what());
  }
}

}  // namespace tear
