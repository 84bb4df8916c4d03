// Scene loading: file reading, --set overrides, and the top-level sections
// (grid, time, transfer, damage, output). Materials, shapes, objects and boundaries are
// parsed in scene_materials.cpp and scene_objects.cpp. Format: SCENE_FORMAT.md.
#include "tear/scene/scene.h"

#include "tear/io/frames.h"
#include "tear/io/mesh_frames.h"
#include "tear/particles/particles.h"
#include "tear/scene/scene_parts.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace tear {

using namespace scene_detail;

SceneError::SceneError(const std::string& file, const std::string& path,
                       const std::string& reason)
    : std::runtime_error(file + ": " + path + ": " + reason),
      file_(file),
      path_(path),
      reason_(reason) {}

namespace {

constexpr double kDefaultMaxDt = 1e-3;


constexpr double kMaxCellsPerAxis = 1 << 24;

json parse_grid(const Reader& r, const json& doc, Scene* s) {
  const json* g = r.find(doc, "grid");
  if (!g) r.fail("grid", "required");
  r.object(*g, "grid", {"dx", "domain_min", "domain_max", "walls"});
  s->dx = r.number(*g, "grid", "dx");
  r.positive(s->dx, "grid.dx");
  s->domain_min = r.vec(*g, "grid", "domain_min");
  s->domain_max = r.vec(*g, "grid", "domain_max");
  for (int i = 0; i < r.dim; ++i)
    r.check(s->domain_min[i] < s->domain_max[i], "grid.domain_max",
            "must be > domain_min in every entry (entry " + std::to_string(i) + ": " +
                num_str(s->domain_max[i]) + " <= " + num_str(s->domain_min[i]) + ")");
  // Cell indices are ints (sampling, grid); a domain this many cells wide is a typo anyway.
  for (int i = 0; i < r.dim; ++i) {
    double cells = (s->domain_max[i] - s->domain_min[i]) / s->dx;
    r.check(cells <= kMaxCellsPerAxis, "grid.dx",
            "too small for the domain: " + num_str(std::ceil(cells)) + " cells along axis " +
                std::to_string(i) + " (at most " + num_str(kMaxCellsPerAxis) + ")");
  }
  s->walls = ContactType(r.choice(*g, "grid", "walls", {"sticky", "slip", "separate", "none"}, 2));
  const char* walls[] = {"sticky", "slip", "separate", "none"};
  return {{"dx", s->dx},
          {"domain_min", vec_json(s->domain_min, r.dim)},
          {"domain_max", vec_json(s->domain_max, r.dim)},
          {"walls", walls[int(s->walls)]}};
}

json parse_time(const Reader& r, const json& doc, Scene* s) {
  const json* t = r.find(doc, "time");
  if (!t) r.fail("time", "required");
  r.object(*t, "time", {"frame_dt", "frames", "cfl", "max_dt"});
  s->frame_dt = r.number(*t, "time", "frame_dt");
  r.positive(s->frame_dt, "time.frame_dt");
  long long frames = r.integer(*t, "time", "frames");
  r.check(frames >= 1 && frames <= 100000000, "time.frames",
          "must be in [1, 1e8], got " + std::to_string(frames));
  s->frames = int(frames);
  s->cfl = r.number(*t, "time", "cfl", 0.4);
  r.check(s->cfl > 0 && s->cfl <= 1, "time.cfl", "must be in (0, 1], got " + num_str(s->cfl));
  s->max_dt = r.number(*t, "time", "max_dt", kDefaultMaxDt);
  r.positive(s->max_dt, "time.max_dt");
  return {{"frame_dt", s->frame_dt}, {"frames", s->frames}, {"cfl", s->cfl},
          {"max_dt", s->max_dt}};
}

// The implicit integrator's Newton solve (solvers/newton.h); stored always, used when
// "integrator" is "implicit".
json parse_implicit(const Reader& r, const json& doc, Scene* s) {
  static const json kEmpty = json::object();
  const json* d = r.find(doc, "implicit");
  if (!d) d = &kEmpty;
  r.object(*d, "implicit",
           {"tolerance", "max_iterations", "cg_tolerance", "cg_max_iterations", "preconditioner",
            "multigrid_after"});
  NewtonSettings& n = s->newton;
  n.tolerance = r.number(*d, "implicit", "tolerance", n.tolerance);
  r.check(n.tolerance > 0 && n.tolerance < 1, "implicit.tolerance",
          "must be in (0, 1), got " + json(n.tolerance).dump());
  n.max_iterations = int(r.integer(*d, "implicit", "max_iterations", n.max_iterations));
  r.check(n.max_iterations >= 1 && n.max_iterations <= 1000, "implicit.max_iterations",
          "must be in [1, 1000], got " + std::to_string(n.max_iterations));
  n.cg_tolerance = r.number(*d, "implicit", "cg_tolerance", n.cg_tolerance);
  r.check(n.cg_tolerance > 0 && n.cg_tolerance < 1, "implicit.cg_tolerance",
          "must be in (0, 1), got " + json(n.cg_tolerance).dump());
  n.cg_max_iterations = int(r.integer(*d, "implicit", "cg_max_iterations", n.cg_max_iterations));
  r.check(n.cg_max_iterations >= 1 && n.cg_max_iterations <= 1000000, "implicit.cg_max_iterations",
          "must be in [1, 1e6], got " + std::to_string(n.cg_max_iterations));
  static const char* kPreconditioners[] = {"auto", "multigrid", "jacobi"};
  s->implicit_preconditioner = ImplicitPreconditioner(
      r.choice(*d, "implicit", "preconditioner", {"auto", "multigrid", "jacobi"}, 0));
  n.cg_escalate_after = int(r.integer(*d, "implicit", "multigrid_after", n.cg_escalate_after));
  r.check(n.cg_escalate_after >= 1 && n.cg_escalate_after <= 1000000, "implicit.multigrid_after",
          "must be in [1, 1e6], got " + std::to_string(n.cg_escalate_after));
  return {{"tolerance", n.tolerance},
          {"max_iterations", n.max_iterations},
          {"cg_tolerance", n.cg_tolerance},
          {"cg_max_iterations", n.cg_max_iterations},
          {"preconditioner", kPreconditioners[int(s->implicit_preconditioner)]},
          {"multigrid_after", n.cg_escalate_after}};
}

// The inextensibility projection's CG solve (mpm/inextensibility.h); stored always, used when a
// material is inextensible.
json parse_inextensibility(const Reader& r, const json& doc, Scene* s) {
  static const json kEmpty = json::object();
  const json* d = r.find(doc, "inextensibility");
  if (!d) d = &kEmpty;
  r.object(*d, "inextensibility", {"tolerance", "max_iterations", "preconditioner"});
  InextensibilitySettings& x = s->inextensibility;
  x.tolerance = r.number(*d, "inextensibility", "tolerance", x.tolerance);
  r.check(x.tolerance > 0 && x.tolerance < 1, "inextensibility.tolerance",
          "must be in (0, 1), got " + json(x.tolerance).dump());
  x.max_iterations = int(r.integer(*d, "inextensibility", "max_iterations", x.max_iterations));
  r.check(x.max_iterations >= 1 && x.max_iterations <= 1000000, "inextensibility.max_iterations",
          "must be in [1, 1e6], got " + std::to_string(x.max_iterations));
  x.preconditioner = InextensibilityPreconditioner(
      r.choice(*d, "inextensibility", "preconditioner", {"cholesky", "jacobi"}, 0));
  return {{"tolerance", x.tolerance},
          {"max_iterations", x.max_iterations},
          {"preconditioner",
           x.preconditioner == InextensibilityPreconditioner::Cholesky ? "cholesky" : "jacobi"}};
}

json parse_damage(const Reader& r, const json& doc, Scene* s) {
  static const json kEmpty = json::object();
  const json* d = r.find(doc, "damage");
  if (!d) d = &kEmpty;
  // Keys of the grid-based implicit solver that tear no longer has (docs/materials.md
  // "Implicit"): say what replaced them rather than "unknown key".
  if (d->is_object()) {
    if (d->contains("transfer"))
      r.fail("damage.transfer",
             "no longer used: the implicit damage solver solves for the particles' damage "
             "directly, with no grid-to-particle transfer; remove the key");
    for (const char* old : {"cg_tolerance", "cg_max_iterations"})
      if (d->contains(old))
        r.fail(key_path("damage", old),
               std::string("replaced by damage.") + (old[3] == 't' ? "tolerance" : "max_iterations") +
                   " (the implicit damage solver is no longer a CG solve on the grid)");
  }
  r.object(*d, "damage",
           {"solver", "l0", "zeta", "tolerance", "max_iterations", "split_fields", "split_damage"});
  DamageSettings& ds = s->damage;
  // Default: the explicit solver (the paper's choice: faster, same cracks) when some material
  // can be damaged, so a material's damage block is never silently ignored; "none" otherwise.
  bool any_damage = false;
  for (const MaterialSpec& m : s->materials) any_damage = any_damage || m.damage.enabled;
  ds.solver = DamageSolver(
      r.choice(*d, "damage", "solver", {"none", "explicit", "implicit"}, any_damage ? 1 : 0));
  ds.l0 = r.number(*d, "damage", "l0", 0.5 * s->dx);
  r.positive(ds.l0, "damage.l0");
  ds.zeta = r.number(*d, "damage", "zeta", 1.0);
  r.positive(ds.zeta, "damage.zeta");
  ds.tolerance = r.number(*d, "damage", "tolerance", ds.tolerance);
  r.check(ds.tolerance > 0 && ds.tolerance < 1, "damage.tolerance",
          "must be in (0, 1), got " + json(ds.tolerance).dump());
  ds.max_iterations = int(r.integer(*d, "damage", "max_iterations", ds.max_iterations));
  r.check(ds.max_iterations >= 1 && ds.max_iterations <= 100000, "damage.max_iterations",
          "must be in [1, 100000], got " + std::to_string(ds.max_iterations));
  ds.split_fields = r.boolean(*d, "damage", "split_fields", ds.split_fields);
  ds.split_damage = r.number(*d, "damage", "split_damage", ds.split_damage);
  r.check(ds.split_damage > 0 && ds.split_damage <= 1, "damage.split_damage",
          "must be in (0, 1], got " + json(ds.split_damage).dump());
  const char* solvers[] = {"none", "explicit", "implicit"};
  return {{"solver", solvers[int(ds.solver)]},
          {"l0", ds.l0},
          {"zeta", ds.zeta},
          {"tolerance", ds.tolerance},
          {"max_iterations", ds.max_iterations},
          {"split_fields", ds.split_fields},
          {"split_damage", ds.split_damage}};
}

// The array of strings at `path`: distinct, each one of `allowed` (`what` names one in errors).
std::vector<std::string> distinct_names(const Reader& r, const json& v, const std::string& path,
                                        const std::vector<std::string>& allowed,
                                        const std::string& what) {
  if (!v.is_array()) r.fail(path, "must be an array of strings, got " + type_desc(v));
  std::string list;
  for (const std::string& a : allowed) list += (list.empty() ? "" : ", ") + a;
  std::vector<std::string> names;
  for (size_t i = 0; i < v.size(); ++i) {
    std::string p = index_path(path, i);
    if (!v[i].is_string()) r.fail(p, "must be a string, got " + type_desc(v[i]));
    std::string name = v[i].get<std::string>();
    if (std::find(allowed.begin(), allowed.end(), name) == allowed.end())
      r.fail(p, "unknown " + what + " \"" + name + "\" (expected one of: " + list + ")");
    for (const std::string& seen : names)
      r.check(seen != name, p, "duplicate " + what + " \"" + name + "\"");
    names.push_back(name);
  }
  return names;
}

// Free text about the scene (what it shows, where it comes from): a string, or an array of
// strings, one per line, so that a long header reads well in the file. Kept as written.
std::string parse_description(const Reader& r, const json& doc) {
  const json* d = r.find(doc, "description");
  if (!d || d->is_null()) return "";
  if (d->is_string()) return d->get<std::string>();
  if (!d->is_array()) r.fail("description", "must be a string or an array of strings, got " +
                                                type_desc(*d));
  std::string text;
  for (size_t i = 0; i < d->size(); ++i) {
    if (!(*d)[i].is_string())
      r.fail(index_path("description", i), "must be a string, got " + type_desc((*d)[i]));
    text += (i ? "\n" : "") + (*d)[i].get<std::string>();
  }
  return text;
}

json parse_output(const Reader& r, const json& doc, Scene* s) {
  static const json kEmpty = json::object();
  const json* o = r.find(doc, "output");
  if (!o) o = &kEmpty;
  r.object(*o, "output", {"every", "formats", "mesh_formats", "checkpoint_every", "fields"});
  long long every = r.integer(*o, "output", "every", 1);
  r.check(every >= 1 && every <= 1000000000, "output.every",
          "must be >= 1, got " + std::to_string(every));
  s->output_every = int(every);
  long long ck = r.integer(*o, "output", "checkpoint_every", 10);
  r.check(ck >= 0 && ck <= 1000000000, "output.checkpoint_every",
          "must be >= 0, got " + std::to_string(ck));
  s->checkpoint_every = int(ck);
  s->formats = {"ply"};
  if (const json* f = r.find(*o, "formats")) {
    s->formats = distinct_names(r, *f, "output.formats", point_formats(), "format");
    // Frames are always written; an empty list would be silently ignored.
    r.check(!s->formats.empty(), "output.formats", "must name at least one format (ply)");
  }
  s->mesh_formats = {"ply"};
  if (const json* f = r.find(*o, "mesh_formats")) {
    s->mesh_formats = distinct_names(r, *f, "output.mesh_formats", mesh_part_formats(), "format");
    r.check(!s->mesh_formats.empty(), "output.mesh_formats",
            "must name at least one format (ply)");
  }
  s->output_fields.clear();
  if (const json* f = r.find(*o, "fields"))
    s->output_fields =
        distinct_names(r, *f, "output.fields", Particles<3>().requestable_columns(), "field");
  return {{"every", s->output_every},
          {"formats", s->formats},
          {"mesh_formats", s->mesh_formats},
          {"checkpoint_every", s->checkpoint_every},
          {"fields", s->output_fields}};
}

json parse_render(const Reader& r, const json& doc, Scene* s) {
  static const json kEmpty = json::object();
  const json* v = r.find(doc, "render");
  if (!v) v = &kEmpty;
  r.object(*v, "render", {"camera", "color", "width", "height", "samples", "surface"});
  RenderSpec& rs = s->render;
  const RenderSpec def;
  const auto& colors = RenderSpec::kColors;
  static_assert(std::size(RenderSpec::kColors) == 6);
  rs.color =
      colors[r.choice(*v, "render", "color",
                      {colors[0], colors[1], colors[2], colors[3], colors[4], colors[5]}, 0)];
  auto bounded = [&](const char* key, long long def, long long lo, long long hi) {
    const long long x = r.integer(*v, "render", key, def);
    r.check(x >= lo && x <= hi, key_path("render", key),
            "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " +
                std::to_string(x));
    return int(x);
  };
  rs.width = bounded("width", def.width, RenderSpec::kMinSize, RenderSpec::kMaxSize);
  rs.height = bounded("height", def.height, RenderSpec::kMinSize, RenderSpec::kMaxSize);
  rs.samples = bounded("samples", def.samples, 1, RenderSpec::kMaxSamples);
  rs.surface = r.boolean(*v, "render", "surface", def.surface);
  json camera = {{"position", nullptr}, {"target", nullptr}, {"up", nullptr}};
  const json* c = r.find(*v, "camera");
  if (c) r.object(*c, "render.camera", {"position", "target", "up", "fov_deg"});
  // Camera vectors are 3D whatever the scene's dim: the camera looks at the z = 0 plane in 2D.
  auto vec3 = [&](const char* key, bool* has, Vec3d* out) {
    const json* e = c ? r.find(*c, key) : nullptr;
    if (!e) return;
    *has = true;
    *out = r.as_vec(*e, key_path("render.camera", key), 3);
    camera[key] = vec_json(*out, 3);
  };
  vec3("position", &rs.has_position, &rs.position);
  vec3("target", &rs.has_target, &rs.target);
  vec3("up", &rs.has_up, &rs.up);
  if (rs.has_up) r.check(rs.up.norm() > 0, "render.camera.up", "must be non-zero");
  if (rs.has_position && rs.has_target)
    r.check(rs.position != rs.target, "render.camera.target",
            "must differ from render.camera.position");
  rs.fov_deg = c ? r.number(*c, "render.camera", "fov_deg", 40) : 40;
  r.check(rs.fov_deg > 0 && rs.fov_deg < 180, "render.camera.fov_deg",
          "must be in (0, 180), got " + num_str(rs.fov_deg));
  camera["fov_deg"] = rs.fov_deg;
  return {{"camera", camera},    {"color", rs.color},     {"width", rs.width},
          {"height", rs.height}, {"samples", rs.samples}, {"surface", rs.surface}};
}

// Top-level sections a scene may leave out (every key has a default): an override may name
// one that the file does not have.
const std::vector<std::string> kOptionalSections = {"implicit", "inextensibility", "damage",
                                                    "output", "render"};

// Sets doc at the dotted `path` to `value`; the parent must exist, or be an optional section.
void apply_override(const std::string& file, json* doc, const std::string& ov) {
  size_t eq = ov.find('=');
  if (eq == std::string::npos || eq == 0)
    throw SceneError(file, "(override)", "override \"" + ov + "\" must look like a.b.c=VALUE");
  std::string path = ov.substr(0, eq), text = ov.substr(eq + 1);
  json value = json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (value.is_discarded()) value = text;
  std::vector<std::string> parts;
  std::stringstream ss(path);
  for (std::string p; std::getline(ss, p, '.');) parts.push_back(p);
  if (path.back() == '.') parts.push_back("");
  json* node = doc;
  std::string walked;
  auto bad = [&](const std::string& why) {
    throw SceneError(file, path, "override \"" + ov + "\": " + why);
  };
  for (size_t i = 0; i < parts.size(); ++i) {
    const std::string& part = parts[i];
    if (part.empty()) bad("empty path component");
    bool last = i + 1 == parts.size();
    if (node->is_object()) {
      if (!last && !node->contains(part)) {
        if (i == 0 && std::count(kOptionalSections.begin(), kOptionalSections.end(), part)) {
          (*node)[part] = json::object();
        } else {
          std::vector<std::string> keys;
          for (auto it = node->begin(); it != node->end(); ++it) keys.push_back(it.key());
          bad("\"" + key_path(walked, part) + "\" does not exist" + did_you_mean(part, keys));
        }
      }
      node = &(*node)[part];
    } else if (node->is_array()) {
      bool digits = part.find_first_not_of("0123456789") == std::string::npos;
      if (!digits || part.size() > 9 || std::stoul(part) >= node->size())
        bad("\"" + key_path(walked, part) + "\" does not exist (array of " +
            entries(node->size()) + ")");
      node = &(*node)[std::stoul(part)];
    } else {
      bad("\"" + walked + "\" is " + type_desc(*node) + ", not an object or array");
    }
    walked = key_path(walked, part);
  }
  *node = value;
}

// `tear run --resolution K`: grid.dx and time.max_dt divided by K (so l0 = 0.5 dx by default
// follows, and the cap on dt keeps its ratio to dx); everything in scene units (shapes, an
// explicit damage.l0, frame times) stays. Objects read from particle files cannot be refined.
void scale_resolution(const std::string& path, json* doc, double k) {
  if (k == 1) return;
  if (!(k > 0) || !std::isfinite(k))
    throw SceneError(path, "(resolution)", "must be a positive number, got " + std::to_string(k));
  if (!doc->is_object()) return;  // parse_scene names the problem
  json& grid = (*doc)["grid"];
  if (grid.is_object() && grid.contains("dx") && grid["dx"].is_number())
    grid["dx"] = grid["dx"].get<double>() / k;
  json& time = (*doc)["time"];
  if (time.is_object()) {
    const double max_dt =
        time.contains("max_dt") && time["max_dt"].is_number() ? time["max_dt"].get<double>()
                                                              : kDefaultMaxDt;
    time["max_dt"] = max_dt / k;
  }
  if (doc->contains("objects") && (*doc)["objects"].is_array()) {
    json& objects = (*doc)["objects"];
    for (size_t i = 0; i < objects.size(); ++i) {
      json& o = objects[i];
      if (o.is_object() && o.contains("shape") && o["shape"].is_object() &&
          o["shape"].value("type", "") == "particles")
        throw SceneError(path, index_path("objects", i) + ".shape",
                         "a particle file keeps its points: --resolution cannot refine it");
      // An FEM body's explicit mesh size refines with the grid (its default is grid.dx).
      if (o.is_object() && o.contains("mesh_size") && o["mesh_size"].is_number())
        o["mesh_size"] = o["mesh_size"].get<double>() / k;
    }
  }
}

}  // namespace

Scene load_scene(const std::string& path, const std::vector<std::string>& overrides,
                 double resolution) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw SceneError(path, "(file)", "is a directory, not a scene file");
  errno = 0;
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    std::string why = errno ? ": " + std::string(std::strerror(errno)) : "";
    throw SceneError(path, "(file)", "cannot open file" + why);
  }
  std::stringstream text;
  text << in.rdbuf();
  return load_scene_text(text.str(), path, overrides, resolution);
}

Scene load_scene_text(const std::string& text, const std::string& path,
                      const std::vector<std::string>& overrides, double resolution) {
  json doc;
  try {
    doc = json::parse(text);
  } catch (const json::parse_error& e) {
    std::string msg = e.what();
    size_t close = msg.find("] ");
    if (msg.rfind("[json.exception", 0) == 0 && close != std::string::npos)
      msg = msg.substr(close + 2);
    throw SceneError(path, "(file)", "invalid JSON: " + msg);
  }
  for (const std::string& ov : overrides) apply_override(path, &doc, ov);
  scale_resolution(path, &doc, resolution);
  return parse_scene(doc, path);
}

Scene parse_scene(const json& doc, const std::string& file) {
  Reader r(file);
  Scene s;
  s.file = file;
  if (!doc.is_object()) r.fail("(root)", "must be an object, got " + type_desc(doc));
  r.object(doc, "",
           {"name", "description", "dim", "seed", "grid", "time", "gravity", "transfer", "flip_ratio",
            "flip_relaxation_time", "integrator", "implicit", "inextensibility", "damage", "materials", "objects",
            "boundaries", "output", "render"});
  long long dim = r.integer(doc, "", "dim");
  r.check(dim == 2 || dim == 3, "dim", "must be 2 or 3, got " + std::to_string(dim));
  s.dim = r.dim = int(dim);
  std::string stem = file.empty() ? "scene" : std::filesystem::path(file).stem().string();
  s.name = r.string(doc, "", "name", stem);
  r.check(!s.name.empty(), "name", "must not be empty");
  s.description = parse_description(r, doc);
  long long seed = r.integer(doc, "", "seed", 1);
  r.non_negative(double(seed), "seed");
  s.seed = uint64_t(seed);

  json out;
  out["name"] = s.name;
  if (!s.description.empty()) out["description"] = doc["description"];
  out["dim"] = s.dim;
  out["seed"] = s.seed;
  out["grid"] = parse_grid(r, doc, &s);
  out["time"] = parse_time(r, doc, &s);
  s.gravity = r.vec(doc, "", "gravity", Vec3d::Zero());
  out["gravity"] = vec_json(s.gravity, s.dim);
  s.transfer = Transfer(r.choice(doc, "", "transfer", {"apic", "pic", "flip"}, 0));
  const char* transfers[] = {"apic", "pic", "flip"};
  out["transfer"] = transfers[int(s.transfer)];
  // Stored always so the resolved scene reloads; only used when transfer is "flip".
  s.flip_ratio = r.number(doc, "", "flip_ratio", 0.95);
  r.check(s.flip_ratio >= 0 && s.flip_ratio <= 1, "flip_ratio",
          "must be in [0, 1], got " + num_str(s.flip_ratio));
  out["flip_ratio"] = s.flip_ratio;
  // The blend as a rate, which does not depend on the step: replaces flip_ratio when set.
  out["flip_relaxation_time"] = nullptr;
  if (r.find(doc, "flip_relaxation_time")) {
    s.flip_relaxation_time = r.number(doc, "", "flip_relaxation_time");
    r.positive(s.flip_relaxation_time, "flip_relaxation_time");
    r.check(s.transfer == Transfer::Flip, "flip_relaxation_time",
            "is FLIP's blend: set \"transfer\": \"flip\" (it is \"" +
                std::string(transfers[int(s.transfer)]) + "\")");
    out["flip_relaxation_time"] = s.flip_relaxation_time;
  }
  s.integrator = Integrator(r.choice(doc, "", "integrator", {"explicit", "implicit"}, 0));
  out["integrator"] = s.integrator == Integrator::Explicit ? "explicit" : "implicit";
  out["implicit"] = parse_implicit(r, doc, &s);
  out["inextensibility"] = parse_inextensibility(r, doc, &s);
  out["materials"] = parse_materials(r, doc, &s);
  out["damage"] = parse_damage(r, doc, &s);  // after the materials: its default depends on them
  if (s.integrator == Integrator::Implicit && s.damage.split_fields)
    r.fail("damage.split_fields",
           "crack fields are not supported by the implicit integrator: remove the key or use "
           "\"integrator\": \"explicit\"");
  for (const MaterialSpec& m : s.materials)
    if (m.inextensibility.enabled && s.damage.split_fields)
      r.fail("damage.split_fields",
             "crack fields are not supported with inextensible materials (materials." + m.name +
                 " is): remove the key");
  out["objects"] = parse_objects(r, doc, &s);
  // FEM bodies (docs/fem.md): a scene is all FEM or all MPM until the two are coupled.
  for (size_t i = 0; i < s.objects.size(); ++i)
    if (s.objects[i].fem != s.objects[0].fem)
      r.fail(index_path("objects", i) + ".simulation",
             std::string("is \"") + (s.objects[i].fem ? "fem" : "mpm") + "\" but objects[0] is \"" +
                 (s.objects[0].fem ? "fem" : "mpm") +
                 "\": FEM and MPM bodies do not share a scene yet (they do not interact); run them "
                 "as two scenes");
  for (size_t i = 0; i < s.objects.size(); ++i)
    if (s.objects[i].consistent_mass && s.integrator != Integrator::Implicit)
      r.fail(index_path("objects", i) + ".mass",
             "\"consistent\" needs \"integrator\": \"implicit\" (an explicit step would solve "
             "the mass matrix every step; it takes lumped masses)");
  if (!s.objects.empty() && s.objects[0].fem && s.damage.solver != DamageSolver::None)
    r.fail("damage.solver", "FEM bodies take no damage yet: remove the materials' damage blocks "
                            "or set \"none\"");
  for (size_t i = 0; i < s.objects.size(); ++i) {
    if (s.objects[i].kind == ObjectKind::Volume) continue;
    // The assembled Hessian that multigrid coarsens has no room for an element's corners'
    // stencils (mpm/implicit_step.h); the damage phases know solids only.
    if (s.integrator == Integrator::Implicit &&
        s.implicit_preconditioner == ImplicitPreconditioner::Multigrid)
      r.fail("implicit.preconditioner",
             "\"multigrid\" does not take codimensional objects (objects[" + std::to_string(i) +
                 "] is one): use \"jacobi\" or \"auto\" (which stays with Jacobi)");
    if (s.damage.solver != DamageSolver::None)
      r.fail("damage.solver",
             "damage does not run beside codimensional objects yet (objects[" + std::to_string(i) +
                 "] is one): remove the materials' damage blocks or set \"none\"");
  }
  out["boundaries"] = parse_boundaries(r, doc, &s);
  out["output"] = parse_output(r, doc, &s);
  out["render"] = parse_render(r, doc, &s);
  s.resolved = std::move(out);
  return s;
}

int default_ppc(int dim) { return dim == 2 ? 4 : 8; }

double particle_spacing(const Scene& s, int ppc) {
  if (ppc <= 0)
    for (const ObjectSpec& o : s.objects) ppc = std::max(ppc, o.ppc);
  return s.dx / std::pow(double(ppc > 0 ? ppc : default_ppc(s.dim)), 1.0 / s.dim);
}

}  // namespace tear
