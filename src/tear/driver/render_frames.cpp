#include "tear/driver/render_frames.h"

#include "tear/driver/command.h"

#include <unistd.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <unordered_set>

#include "tear/grid/collider.h"
#include "tear/io/atomic_file.h"
#include "tear/io/frames.h"
#include "tear/render/legend.h"
#include "tear/render/render.h"
#include "tear/render/video.h"
#include "tear/scene/scene.h"

namespace tear {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

// What the renderer needs from a scene: which way is up (against gravity; without gravity the
// camera's up when one is given, else +y), floors, particle sizes, names.
RenderLook look_of(const Scene& s, const RenderSettings& settings) {
  RenderLook look;
  look.dim = s.dim;
  if (s.gravity.norm() > 0) {
    look.up = -s.gravity.normalized();
    look.falls = true;
  } else if (settings.camera_up) {
    look.up = settings.camera_up->normalized();
  }
  // Floors: half spaces whose solid side is below (outward normal along up), and the domain's
  // lower wall when walls hold the particles in.
  for (const Collider& b : s.boundaries) {
    if (b.shape.type != Shape::Type::HalfSpace) continue;
    const Vec3d n = (b.shape.transform.rotate * b.shape.normal).normalized();
    if (n.dot(look.up) > 0.999)
      look.floors.push_back(b.shape.transform.to_world(b.shape.point).dot(look.up));
  }
  if (s.walls != ContactType::None)
    for (int a = 0; a < s.dim; ++a) {
      if (look.up[a] > 0.999) look.floors.push_back(s.domain_min[a]);
      if (look.up[a] < -0.999) look.floors.push_back(-s.domain_max[a]);
    }
  // Spheres just touching on the sampling lattice: radius half the particle spacing.
  std::vector<int> ppc(s.materials.size(), 0);
  for (const ObjectSpec& o : s.objects) {
    std::vector<int> materials = {o.material};
    for (const RegionSpec& r : o.regions) materials.push_back(r.material);
    for (int m : materials)
      if (m >= 0 && size_t(m) < ppc.size()) ppc[size_t(m)] = std::max(ppc[size_t(m)], o.ppc);
  }
  for (size_t m = 0; m < s.materials.size(); ++m) {
    const int n = ppc[m] > 0 ? ppc[m] : default_ppc(s.dim);  // a material no object uses
    look.material_radius.push_back(0.5 * particle_spacing(s, n));
    look.material_names.push_back(s.materials[m].name);
  }
  look.radius = 0.5 * particle_spacing(s, default_ppc(s.dim));
  look.spacing = particle_spacing(s);
  look.mesh_gap = s.dx;
  return look;
}

RenderSettings settings_of(const RenderSpec& spec, const RenderOverrides& o) {
  RenderSettings st;
  st.color = parse_color_by(o.color.value_or(spec.color));
  st.width = o.width.value_or(spec.width);
  st.height = o.height.value_or(spec.height);
  st.samples = o.samples.value_or(spec.samples);
  st.surface = o.surface || spec.surface;
  if (spec.has_position) st.camera_position = spec.position;
  if (spec.has_target) st.camera_target = spec.target;
  if (spec.has_up) st.camera_up = spec.up;
  if (o.camera_position) st.camera_position = o.camera_position;
  if (o.camera_target) st.camera_target = o.camera_target;
  if (o.camera_up) st.camera_up = o.camera_up;
  st.fov_deg = o.fov_deg.value_or(spec.fov_deg);
  st.radius = o.radius.value_or(0);
  if (o.color_max) st.range_max = *o.color_max;
  const int lo = RenderSpec::kMinSize, hi = RenderSpec::kMaxSize;
  if (st.width < lo || st.height < lo || st.width > hi || st.height > hi)
    throw std::runtime_error("picture size " + std::to_string(st.width) + "x" +
                             std::to_string(st.height) + ": width and height must be in [" +
                             std::to_string(lo) + ", " + std::to_string(hi) + "]");
  if (st.samples < 1 || st.samples > RenderSpec::kMaxSamples)
    throw std::runtime_error("--samples " + std::to_string(st.samples) + ": must be in [1, " +
                             std::to_string(RenderSpec::kMaxSamples) + "]");
  if (!(st.fov_deg > 0 && st.fov_deg < 180))
    throw std::runtime_error("--fov " + std::to_string(st.fov_deg) + ": must be in (0, 180)");
  if (o.radius && !(*o.radius > 0)) throw std::runtime_error("--radius: must be > 0");
  if (o.color_max && !(*o.color_max > 0)) throw std::runtime_error("--color-max: must be > 0");
  if (st.camera_up && !(st.camera_up->norm() > 0))
    throw std::runtime_error("--camera-up: must be non-zero");
  if (st.camera_position && st.camera_target && *st.camera_position == *st.camera_target)
    throw std::runtime_error("--camera-position equals the camera target");
  return st;
}

std::string png_path(const std::string& dir, int frame) {
  char name[32];
  std::snprintf(name, sizeof(name), "%05d.png", frame);
  return (fs::path(dir) / "render" / name).string();
}

std::string caption_of(int frame, double frame_dt) {
  return "FRAME " + std::to_string(frame) + "   T=" + label_number(frame * frame_dt);
}

// Playback rate: the run's own (one rendered frame per frame_dt times the usual gap between
// rendered frames), kept between 6 and 60 frames per second.
double video_fps(const std::vector<int>& frames, double frame_dt) {
  std::vector<int> gaps;
  for (size_t i = 1; i < frames.size(); ++i) gaps.push_back(frames[i] - frames[i - 1]);
  int gap = 1;
  if (!gaps.empty()) {
    std::nth_element(gaps.begin(), gaps.begin() + long(gaps.size() / 2), gaps.end());
    gap = std::max(1, gaps[gaps.size() / 2]);
  }
  const double fps = frame_dt > 0 ? 1 / (frame_dt * gap) : 24;
  return std::clamp(std::isfinite(fps) ? fps : 24.0, 6.0, 60.0);
}

// Encodes the video; a missing ffmpeg is a warning given once per process.
std::string encode_video(const std::string& dir, const std::vector<int>& frames, double frame_dt,
                         int threads) {
  static bool warned = false;
  const std::string out = (fs::path(dir) / "preview.mp4").string();
  std::vector<std::string> pngs;
  for (int f : frames) pngs.push_back(png_path(dir, f));
  if (make_video(pngs, video_fps(frames, frame_dt), out, threads)) return out;
  if (!warned)
    std::fprintf(stderr,
                 "tear: warning: ffmpeg not found on PATH: kept the pictures in %s, no %s\n",
                 (fs::path(dir) / "render").string().c_str(), out.c_str());
  warned = true;
  return "";
}

// Where the colliders go during the run: their boxes at 33 times from start to end (or the
// run's end), clipped to the grid domain. A picture fitted before the run (tear run --render)
// knows only frame 0 besides; torn pieces go where the colliders pull them.
std::vector<Eigen::Vector3d> collider_reach(const Scene& s) {
  std::vector<Eigen::Vector3d> out;
  const double t_end = s.frames * s.frame_dt;
  for (const Collider& c : s.boundaries) {
    if (c.shape.type == Shape::Type::HalfSpace) continue;
    Vec3d lo, hi;
    c.shape.bounds(&lo, &hi);
    const double t0 = std::max(0.0, c.start), t1 = std::min(t_end, c.end);
    if (t1 < t0) continue;
    for (int k = 0; k <= 32; ++k) {
      const ColliderState st = collider_state(c, t0 + (t1 - t0) * k / 32);
      for (int corner = 0; corner < 8; ++corner) {
        const Vec3d q((corner & 1) ? hi.x() : lo.x(), (corner & 2) ? hi.y() : lo.y(),
                      (corner & 4) ? hi.z() : lo.z());
        Vec3d w = st.center0 + st.displacement + st.rotation * (q - st.center0);
        for (int d = 0; d < 3; ++d)
          w[d] = d < s.dim ? std::clamp(w[d], s.domain_min[d], s.domain_max[d]) : 0.0;
        out.push_back(w);
      }
    }
  }
  return out;
}

// Where the body goes during a finished run: in up to 16 of its frames, spread from the first
// to the last, the box of the middle 99 % of the particles along each axis (stray fragments do
// not shrink the picture), clipped to the grid domain. Every frame of the run is looked at, not
// only those being drawn, so that drawing a range gives the same pictures as drawing them all.
std::vector<Eigen::Vector3d> frames_reach(const std::string& dir, const Scene& s) {
  const std::vector<FrameFile> all = list_frames(dir);
  std::vector<Eigen::Vector3d> out;
  const size_t n = all.size(), picks = std::min<size_t>(n, 16);
  for (size_t k = 0; k < picks; ++k) {
    const size_t i = picks == 1 ? 0 : k * (n - 1) / (picks - 1);
    std::vector<Eigen::Vector3d> x = positions(read_frame(all[i].path));
    const std::vector<Eigen::Vector3d> mesh = mesh_points(read_mesh_parts(dir, all[i].frame));
    x.insert(x.end(), mesh.begin(), mesh.end());
    if (x.empty()) continue;
    Vec3d lo = Vec3d::Zero(), hi = Vec3d::Zero();
    std::vector<double> c(x.size());
    for (int d = 0; d < s.dim; ++d) {
      for (size_t j = 0; j < x.size(); ++j) c[j] = x[j][d];
      const size_t a = c.size() / 200, b = c.size() - 1 - a;
      std::nth_element(c.begin(), c.begin() + a, c.end());
      lo[d] = std::clamp(c[a], s.domain_min[d], s.domain_max[d]);
      std::nth_element(c.begin(), c.begin() + b, c.end());
      hi[d] = std::clamp(c[b], s.domain_min[d], s.domain_max[d]);
    }
    for (int corner = 0; corner < 8; ++corner)
      out.emplace_back((corner & 1) ? hi.x() : lo.x(), (corner & 2) ? hi.y() : lo.y(),
                       (corner & 4) ? hi.z() : lo.z());
  }
  return out;
}

// The frame column a colour map reads that only some runs write (scene output.fields), or null.
const char* optional_column(ColorBy c) {
  return c == ColorBy::DrivingForce || c == ColorBy::DamageLaplacian ? color_by_name(c) : nullptr;
}

// A frame sequence drawn with one camera.
struct Sequence {
  std::string dir;
  RenderSettings settings;  // before look, which takes the camera's up from it
  RenderLook look;
  Renderer renderer;
  std::optional<Stage> stage;
  double frame_dt = 1.0 / 24;
  bool auto_range = true;  // the colour map's top follows the frames seen (color_range_top)
  double top = 0;
  std::vector<Eigen::Vector3d> reach;  // what the picture must hold besides the first frame
  std::vector<Collider> colliders;     // drawn where they are at each frame's time
  bool rest_space = false;
  std::optional<PointTable> rest;  // frame 0's id, x, y, z (rest space)
  std::vector<PointTable> rest_meshes;  // frame 0's mesh vertices' x, y, z, by part

  Sequence(const std::string& d, const Scene& scene, const RenderOverrides& o)
      : dir(d), settings(settings_of(scene.render, o)), look(look_of(scene, settings)) {
    frame_dt = scene.frame_dt;
    auto_range = !o.color_max;
    rest_space = o.rest_space;
    if (!rest_space) reach = collider_reach(scene);  // rest space stays where frame 0 is
    // Colliders have no rest position: rest-space pictures show the body alone.
    if (o.colliders && !rest_space) colliders = scene.boundaries;
  }

  // Keeps frame 0's positions for rest-space pictures.
  void set_rest(const PointTable& frame0, const std::vector<MeshPart>& meshes0) {
    if (!rest_space || rest) return;
    auto keep = [](const PointTable& from, PointTable* to) {
      to->count = from.count;
      for (const char* name : {"id", "x", "y", "z"})
        if (from.has(name)) to->add(name, ColumnType::Float64, from.column(name));
    };
    rest.emplace();
    keep(frame0, &*rest);
    for (const MeshPart& part : meshes0) keep(part.vertices, &rest_meshes.emplace_back());
  }

  // The meshes as drawn: in rest space, each vertex at its frame-0 position (mesh vertices are
  // never reordered); in world space the meshes themselves.
  const std::vector<MeshPart>& shown(int frame, const std::vector<MeshPart>& meshes) {
    if (!rest_space) return meshes;
    shown_meshes_ = meshes;
    for (size_t k = 0; k < shown_meshes_.size(); ++k) {
      PointTable& t = shown_meshes_[k].vertices;
      if (k >= rest_meshes.size() || rest_meshes[k].count != t.count)
        throw std::runtime_error("frame " + std::to_string(frame) + ": its " +
                                 shown_meshes_[k].name +
                                 " mesh is not that of frame 0, so it cannot be drawn in rest "
                                 "space");
      for (size_t c = 0; c < t.names.size(); ++c)
        if ((t.names[c] == "x" || t.names[c] == "y" || t.names[c] == "z") &&
            rest_meshes[k].has(t.names[c]))
          t.columns[c] = rest_meshes[k].column(t.names[c]);
    }
    return shown_meshes_;
  }
  std::vector<MeshPart> shown_meshes_;  // shown()'s rest-space meshes

  // The frame as drawn: in rest space, each particle at its frame-0 position (same ids, same
  // order: frames list particles by id), with this frame's colours, in `shown_`; in world
  // space the frame itself.
  const PointTable& shown(int frame, const PointTable& table) {
    if (!rest_space) return table;
    PointTable& t = shown_;
    t = table;
    if (!rest) throw std::runtime_error("rest space needs frame 0 of the run");
    const bool same = table.count == rest->count &&
                      (!table.has("id") || !rest->has("id") ||
                       table.column("id") == rest->column("id"));
    if (!same)
      throw std::runtime_error("frame " + std::to_string(frame) +
                               ": its particles are not those of frame 0 (ids differ), so it "
                               "cannot be drawn in rest space");
    for (size_t c = 0; c < t.names.size(); ++c)
      if ((t.names[c] == "x" || t.names[c] == "y" || t.names[c] == "z") && rest->has(t.names[c]))
        t.columns[c] = rest->column(t.names[c]);
    return t;
  }
  PointTable shown_;  // shown()'s rest-space frame

  void fit(int frame, const PointTable& first, const std::vector<MeshPart>& meshes) {
    std::vector<Eigen::Vector3d> also = reach;
    const std::vector<Eigen::Vector3d> points = mesh_points(shown(frame, meshes));
    also.insert(also.end(), points.begin(), points.end());
    stage = fit_stage(shown(frame, first), look, settings, also);
  }

  void see_range(const PointTable& t, const std::vector<MeshPart>& meshes) {
    if (!auto_range) return;
    top = std::max(top, color_range_top(t, settings.color));
    for (const MeshPart& part : meshes)
      top = std::max(top, color_range_top(part.vertices, settings.color));
  }

  // The colliders' shapes where they are at the frame's time (those active then).
  std::vector<Shape> colliders_at(int frame) const {
    std::vector<Shape> out;
    for (const Collider& c : colliders) {
      const ColliderState state = collider_state(c, frame * frame_dt);
      if (state.active) out.push_back(placed_shape(c, state));
    }
    return out;
  }

  // Throws when the frame lacks the optional column the colour map reads; `source` names the
  // frame (its file).
  void check(const PointTable& table, const std::string& source) const {
    if (const char* column = optional_column(settings.color); column && !table.has(column))
      throw std::runtime_error(source + ": no column '" + column + "' for --color " + column +
                               ": the run did not write it (list \"" + column +
                               "\" in the scene's output.fields and run it again)");
  }

  // The particles drawn as spheres: all but the FEM bodies' nodes (the vertices of the "fem"
  // mesh part, by id), which are drawn as their bodies' surfaces.
  const PointTable& spheres(const PointTable& table, const std::vector<MeshPart>& meshes) {
    const MeshPart* fem = nullptr;
    for (const MeshPart& part : meshes)
      if (part.name == "fem") fem = &part;
    if (!fem || !table.has("id") || !fem->vertices.has("id")) return table;
    const std::vector<double>& node_ids = fem->vertices.column("id");
    const std::unordered_set<double> nodes(node_ids.begin(), node_ids.end());
    const std::vector<double>& ids = table.column("id");
    std::vector<size_t> keep;
    for (size_t r = 0; r < table.count; ++r)
      if (!nodes.count(ids[r])) keep.push_back(r);
    spheres_ = PointTable();
    spheres_.count = keep.size();
    spheres_.names = table.names;
    spheres_.types = table.types;
    for (const std::vector<double>& column : table.columns) {
      std::vector<double>& out = spheres_.columns.emplace_back();
      for (size_t r : keep) out.push_back(column[r]);
    }
    return spheres_;
  }
  PointTable spheres_;

  void draw(int frame, const PointTable& table, const std::vector<MeshPart>& meshes,
            const std::string& source) {
    check(table, source);
    if (!stage) fit(frame, table, meshes);
    if (auto_range) settings.range_max = top > 0 ? top : 1;
    const Image image = renderer.render(
        spheres(shown(frame, table), meshes), look, *stage, settings,
        caption_of(frame, frame_dt) + (rest_space ? "   REST SPACE" : ""), colliders_at(frame),
        shown(frame, meshes));
    write_file_atomic(png_path(dir, frame), encode_png(image));
  }
};

}  // namespace

int render_frames(const RenderOptions& o) {
  FrameRange range;
  try {
    range = parse_frame_range(o.frames);
  } catch (const std::exception& e) {
    return fail(e.what(), 2);
  }
  try {
    const auto limit = limit_threads(o.threads);
    const Clock::time_point start = Clock::now();
    const std::vector<FrameFile> files = frames_in_range(o.dir, range);
    const std::string scene_path = (fs::path(o.dir) / "scene.json").string();
    if (!fs::exists(scene_path))
      return fail(scene_path + ": missing (is " + o.dir + " the output folder of tear run?)");
    const Scene scene = load_scene(scene_path);
    Sequence seq(o.dir, scene, o.overrides);
    if (!seq.rest_space) {  // the run is over: frame the whole of it
      const std::vector<Eigen::Vector3d> frames = frames_reach(o.dir, scene);
      seq.reach.insert(seq.reach.end(), frames.begin(), frames.end());
    }
    if (seq.auto_range && has_range(seq.settings.color))
      for (const FrameFile& f : files)  // the run's top
        seq.see_range(read_frame(f.path), read_mesh_parts(o.dir, f.frame));
    if (seq.rest_space) {
      const std::vector<FrameFile> all = list_frames(o.dir);
      if (all.empty() || all.front().frame != 0)
        return fail(o.dir + ": no frame 0 to take the rest positions from (--space rest)");
      seq.set_rest(read_frame(all.front().path), read_mesh_parts(o.dir, 0));
    }
    make_directories((fs::path(o.dir) / "render").string());
    const bool tty = ::isatty(STDERR_FILENO) != 0;
    std::vector<int> done;
    for (size_t i = 0; i < files.size(); ++i) {
      const PointTable table = read_frame(files[i].path);
      const std::vector<MeshPart> meshes = read_mesh_parts(o.dir, files[i].frame);
      if (i == 0) {
        seq.check(table, files[i].path);
        // Fitted to the run's first frame (and the reach), whichever frames are drawn, so that
        // drawing a range gives the pictures of drawing them all.
        const FrameFile first = list_frames(o.dir).front();
        if (first.frame == files[i].frame)
          seq.fit(first.frame, table, meshes);
        else
          seq.fit(first.frame, read_frame(first.path), read_mesh_parts(o.dir, first.frame));
        if (!o.quiet) {
          const Camera& c = seq.stage->camera;
          std::fprintf(stderr, "camera %g,%g,%g  target %g,%g,%g  fov %g\n", c.position.x(),
                       c.position.y(), c.position.z(), c.target.x(), c.target.y(), c.target.z(),
                       c.fov_deg);
        }
      }
      seq.draw(files[i].frame, table, meshes, files[i].path);
      done.push_back(files[i].frame);
      if (!o.quiet) {
        const double wall = std::chrono::duration<double>(Clock::now() - start).count();
        const size_t n = i + 1, total = files.size();
        char line[160];
        std::snprintf(line, sizeof(line), "render %zu/%zu  frame %d  %.2f s/frame  ETA %s", n,
                      total, files[i].frame, wall / double(n),
                      clock_text(wall / double(n) * double(total - n)).c_str());
        const size_t every = std::max<size_t>(1, total / 20);
        if (tty)
          std::fprintf(stderr, "\r%s\033[K%s", line, n == total ? "\n" : "");
        else if (n == total || n % every == 0)
          std::fprintf(stderr, "%s\n", line);
        std::fflush(stderr);
      }
    }
    std::string video;
    if (o.overrides.video) video = encode_video(o.dir, done, scene.frame_dt, o.threads);
    const double wall = std::chrono::duration<double>(Clock::now() - start).count();
    std::printf("rendered %zu frames (%dx%d, %s) to %s in %.1f s%s\n", done.size(),
                seq.settings.width, seq.settings.height, color_by_name(seq.settings.color),
                (fs::path(o.dir) / "render").string().c_str(), wall,
                video.empty() ? "" : ("; video " + video).c_str());
    return 0;
  } catch (const std::exception& e) {
    return fail(e.what());
  }
}

struct RunRenderer::Impl {
  Sequence seq;
  int threads;
  Impl(const std::string& dir, const Scene& scene, const RenderOverrides& o, int t)
      : seq(dir, scene, o), threads(t) {}
  bool video = true;
};

RunRenderer::RunRenderer(const std::string& dir, const Scene& scene,
                         const RenderOverrides& overrides, int threads)
    : impl_(std::make_unique<Impl>(dir, scene, overrides, threads)) {
  impl_->video = overrides.video;
  const char* column = optional_column(impl_->seq.settings.color);
  const std::vector<std::string>& fields = scene.output_fields;
  if (column && std::find(fields.begin(), fields.end(), column) == fields.end())
    throw std::runtime_error(std::string("--color ") + column + ": the run does not write '" +
                             column + "' (list \"" + column + "\" in the scene's output.fields)");
}

RunRenderer::~RunRenderer() = default;

void RunRenderer::clear() {
  const fs::path dir(impl_->seq.dir);
  fs::remove_all(dir / "render");
  fs::remove(dir / "preview.mp4");
}

void RunRenderer::resume(int frame) {
  Sequence& seq = impl_->seq;
  make_directories((fs::path(seq.dir) / "render").string());
  for (const FrameFile& f : list_frames(seq.dir)) {
    if (f.frame > frame) break;
    const PointTable table = read_frame(f.path);
    const std::vector<MeshPart> meshes = read_mesh_parts(seq.dir, f.frame);
    if (f.frame == 0) seq.set_rest(table, meshes);
    if (!seq.stage) seq.fit(f.frame, table, meshes);  // frame 0: the uninterrupted run's camera
    seq.see_range(table, meshes);
    if (!fs::exists(png_path(seq.dir, f.frame))) seq.draw(f.frame, table, meshes, f.path);
  }
}

void RunRenderer::render(int frame, const PointTable& table, const std::vector<MeshPart>& meshes) {
  Sequence& seq = impl_->seq;
  if (!seq.stage) make_directories((fs::path(seq.dir) / "render").string());
  if (frame == 0) seq.set_rest(table, meshes);
  seq.see_range(table, meshes);
  seq.draw(frame, table, meshes, "frame " + std::to_string(frame));
}

std::string RunRenderer::finish() {
  Sequence& seq = impl_->seq;
  std::vector<int> frames;
  for (const FrameFile& f : list_frames(seq.dir))
    if (fs::exists(png_path(seq.dir, f.frame))) frames.push_back(f.frame);
  const std::string pictures = (fs::path(seq.dir) / "render").string();
  if (frames.empty() || !impl_->video)
    return "rendered " + std::to_string(frames.size()) + " frames to " + pictures;
  const std::string video = encode_video(seq.dir, frames, seq.frame_dt, impl_->threads);
  return "rendered " + std::to_string(frames.size()) + " frames to " + pictures +
         (video.empty() ? "" : "; video " + video);
}

}  // namespace tear
