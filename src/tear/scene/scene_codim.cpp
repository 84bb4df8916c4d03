// Codimensional objects: "objects[i]" with "kind" "surface" (cloth) or "curves" (yarn, hair)
// (docs/scene_reference.md "Cloth, yarn and hair"). Each becomes a mesh in world space, checked
// here so that a degenerate one is refused before anything runs.
#include "tear/io/mesh_io.h"
#include "tear/materials/registry.h"
#include "tear/scene/scene_parts.h"

#include <cmath>
#include <cstdio>

namespace tear::scene_detail {

namespace {

// A pair of numbers or integers at obj[key].
std::array<double, 2> pair_of(const Reader& r, const json& obj, const std::string& path,
                              const char* key) {
  const std::string kp = key_path(path, key);
  const json* v = r.find(obj, key);
  if (!v) r.fail(kp, "required (an array of 2 numbers)");
  if (!v->is_array() || v->size() != 2)
    r.fail(kp, "must be an array of 2 numbers, got " +
                   (v->is_array() ? entries(v->size()) : type_desc(*v)));
  return {r.as_number((*v)[0], index_path(kp, 0)), r.as_number((*v)[1], index_path(kp, 1))};
}

// The mesh file of a "mesh" shape: its triangles (surface) or segments (curves).
CodimMesh read_codim_mesh(const Reader& r, const json& j, const std::string& path, int manifold,
                          json* out) {
  const std::string fp = key_path(path, "file");
  const std::string file = scene_file(r, j, path, out);
  TriMesh t;
  try {
    t = read_mesh_file(file);
  } catch (const std::exception& e) {
    r.fail(fp, e.what());
  }
  CodimMesh mesh;
  mesh.manifold = manifold;
  for (const Eigen::Vector3f& v : t.vertices) mesh.vertices.push_back(v.cast<double>());
  if (manifold == 2) {
    if (t.triangles.empty())
      r.fail(fp, "'" + file + "' has no faces" +
                     (t.segments.empty() ? "" : " (its lines are curves: \"kind\": \"curves\")"));
    for (const auto& f : t.triangles) mesh.elements.push_back({uint32_t(f[0]), uint32_t(f[1]), uint32_t(f[2])});
  } else {
    if (t.segments.empty())
      r.fail(fp, "'" + file + "' has no lines (OBJ \"l\" statements or a PLY edge element)" +
                     (t.triangles.empty() ? "" : "; its faces are a surface: \"kind\": \"surface\""));
    for (const auto& s : t.segments) mesh.elements.push_back({uint32_t(s[0]), uint32_t(s[1]), 0});
  }
  return mesh;
}

}  // namespace

json parse_codim_object(const Reader& r, const json& o, const std::string& path,
                        const Scene& scene, size_t index, ObjectSpec* spec) {
  const bool surface = spec->kind == ObjectKind::Surface;
  const char* size_key = surface ? "thickness" : "radius";
  if (surface)
    r.object(o, path, {"kind", "shape", "material", "thickness", "velocity", "angular_velocity", "fibers"});
  else
    r.object(o, path, {"kind", "shape", "material", "radius", "velocity", "angular_velocity"});
  if (surface && r.dim != 3)
    r.fail(key_path(path, "kind"), "a \"surface\" needs a 3D scene (dim 3); 2D has \"curves\"");
  json out = {{"kind", surface ? "surface" : "curves"}};
  const json* sj = r.find(o, "shape");
  const std::string sp = key_path(path, "shape");
  if (!sj) r.fail(sp, "required");
  if (!sj->is_object()) r.fail(sp, "must be an object, got " + type_desc(*sj));
  const int manifold = surface ? 2 : 1;
  const int type = surface ? r.choice(*sj, sp, "type", {"sheet", "mesh"})
                           : r.choice(*sj, sp, "type", {"rope", "mesh", "strands", "knit"});
  json shape_out = {{"type", (*sj)["type"]}};
  CodimMesh mesh;
  if (type == 1) {
    r.object(*sj, sp, {"type", "file", "transform"});
    mesh = read_codim_mesh(r, *sj, sp, manifold, &shape_out);
  } else if (type == 2) {
    r.object(*sj, sp, {"type", "center", "radius", "direction", "cap_angle", "count", "length",
                       "segments", "transform"});
    const Vec3d center = r.vec(*sj, sp, "center");
    const double radius = r.number(*sj, sp, "radius");
    r.positive(radius, key_path(sp, "radius"));
    const Vec3d direction = r.vec(*sj, sp, "direction", Vec3d::UnitY());
    r.check(direction.norm() > 0, key_path(sp, "direction"), "must be non-zero");
    const double cap = r.number(*sj, sp, "cap_angle", 60.0);
    r.check(cap >= 0 && cap <= 180, key_path(sp, "cap_angle"),
            "must be in [0, 180] degrees, got " + num_str(cap));
    const long long count = r.integer_in(*sj, sp, "count", 1, 10000000);
    const double length = r.number(*sj, sp, "length");
    r.positive(length, key_path(sp, "length"));
    const long long segments = r.integer_in(*sj, sp, "segments", 1, 100000);
    r.check(count == 1 || cap > 0, key_path(sp, "cap_angle"),
            "must be > 0 for more than one strand");
    mesh = make_strands(center, radius, direction, cap, int(count), length, int(segments), r.dim);
    shape_out["center"] = vec_json(center, r.dim);
    shape_out["radius"] = radius;
    shape_out["direction"] = vec_json(direction, r.dim);
    shape_out["cap_angle"] = cap;
    shape_out["count"] = count;
    shape_out["length"] = length;
    shape_out["segments"] = segments;
  } else if (type == 3) {
    if (r.dim != 3)
      r.fail(key_path(sp, "type"), "a \"knit\" swatch needs a 3D scene (dim 3): its courses interlock in depth");
    r.object(*sj, sp, {"type", "center", "size", "wales", "courses", "segments_per_loop", "transform"});
    const Vec3d center = r.vec(*sj, sp, "center");
    const std::array<double, 2> size = pair_of(r, *sj, sp, "size");
    for (int k = 0; k < 2; ++k) r.positive(size[size_t(k)], index_path(key_path(sp, "size"), size_t(k)));
    const int wales = int(r.integer_in(*sj, sp, "wales", 1, 100000)),
              courses = int(r.integer_in(*sj, sp, "courses", 1, 100000)),
              per_loop = int(r.integer_in(*sj, sp, "segments_per_loop", 4, 1000, 16));
    r.check(double(wales) * courses * per_loop <= 1e8, sp, "wales x courses x segments_per_loop must be at most 1e8");
    const double sz[2] = {size[0], size[1]};
    mesh = make_knit(center, sz, wales, courses, per_loop);
    shape_out["center"] = vec_json(center, 3);
    shape_out["size"] = {size[0], size[1]};
    shape_out["wales"] = wales;
    shape_out["courses"] = courses;
    shape_out["segments_per_loop"] = per_loop;
  } else if (surface) {
    r.object(*sj, sp, {"type", "center", "size", "resolution", "triangulation", "transform"});
    const Vec3d center = r.vec(*sj, sp, "center");
    const std::array<double, 2> size = pair_of(r, *sj, sp, "size");
    const std::array<double, 2> res = pair_of(r, *sj, sp, "resolution");
    for (int k = 0; k < 2; ++k) {
      r.positive(size[size_t(k)], index_path(key_path(sp, "size"), size_t(k)));
      r.check(res[size_t(k)] >= 1 && res[size_t(k)] <= 4096 && res[size_t(k)] == std::floor(res[size_t(k)]),
              index_path(key_path(sp, "resolution"), size_t(k)),
              "must be a whole number of quads in [1, 4096], got " + num_str(res[size_t(k)]));
    }
    const bool random = r.choice(*sj, sp, "triangulation", {"regular", "random"}, 0) == 1;
    const double sz[2] = {size[0], size[1]};
    const int n[2] = {int(res[0]), int(res[1])};
    mesh = make_sheet(center, sz, n, random, scene.seed * 0x9E3779B97F4A7C15ull + index);
    shape_out["center"] = vec_json(center, 3);
    shape_out["size"] = {size[0], size[1]};
    shape_out["resolution"] = {n[0], n[1]};
    shape_out["triangulation"] = random ? "random" : "regular";
  } else {
    r.object(*sj, sp, {"type", "from", "to", "segments", "transform"});
    const Vec3d from = r.vec(*sj, sp, "from"), to = r.vec(*sj, sp, "to");
    const long long segments = r.integer_in(*sj, sp, "segments", 1, 10000000);
    r.check((to - from).norm() > 0, key_path(sp, "to"), "must differ from \"from\"");
    mesh = make_rope(from, to, int(segments));
    shape_out["from"] = vec_json(from, r.dim);
    shape_out["to"] = vec_json(to, r.dim);
    shape_out["segments"] = segments;
  }
  ShapeTransform transform;
  shape_out["transform"] = parse_transform(r, *sj, sp, &transform);
  transform_vertices(&mesh, [&](const Vec3d& v) { return transform.to_world(v); });
  if (r.dim == 2)  // rotations about z keep z = 0 up to round-off: exactly 0
    transform_vertices(&mesh, [](Vec3d v) { v.z() = 0; return v; });
  out["shape"] = shape_out;
  const std::string where = type == 1 ? "'" + shape_out["file"].get<std::string>() + "': " : "";
  const std::string defect = find_mesh_defect(mesh, r.dim);
  if (!defect.empty()) r.fail(sp, where + defect);
  // Kept one cell inside the domain, as every particle is (mpm/phases.h KeptBox).
  for (size_t v = 0; v < mesh.vertices.size(); ++v) {
    const Vec3d& x = mesh.vertices[v];
    for (int d = 0; d < r.dim; ++d)
      if (!(x[d] > scene.domain_min[d] + scene.dx && x[d] < scene.domain_max[d] - scene.dx)) {
        char at[96];  // %.6g: a file's float coordinates read as they were written
        if (r.dim == 3)
          std::snprintf(at, sizeof at, "(%.6g, %.6g, %.6g)", x[0], x[1], x[2]);
        else
          std::snprintf(at, sizeof at, "(%.6g, %.6g)", x[0], x[1]);
        r.fail(sp, where + "vertex " + std::to_string(v) + " " + at +
                       " is outside the grid domain less one cell (dx) at each face");
      }
  }

  spec->material = material_index(r, o, path, scene, &out);
  const Model model = scene.materials[size_t(spec->material)].params.model;
  if (model_codimension(model) != manifold)
    r.fail(key_path(path, "material"),
           "material \"" + out["material"].get<std::string>() + "\" is " + model_name(model) +
               ", not a model for " + (surface ? "surfaces (surface_qr)" : "curves (curve_qr)"));
  const double extent = r.number(o, path, size_key);
  r.positive(extent, key_path(path, size_key));
  out[size_key] = extent;
  (surface ? spec->thickness : spec->radius) = extent;
  spec->velocity = r.vec(o, path, "velocity", Vec3d::Zero());
  out["velocity"] = vec_json(spec->velocity, r.dim);
  if (r.dim == 2) {
    spec->angular_velocity = Vec3d(0, 0, r.number(o, path, "angular_velocity", 0.0));
    out["angular_velocity"] = spec->angular_velocity.z();
  } else {
    spec->angular_velocity = r.vec(o, path, "angular_velocity", Vec3d::Zero());
    out["angular_velocity"] = vec_json(spec->angular_velocity, 3);
  }
  if (surface) {
    // The warp: a constant direction (the in-plane fiber stiffness acts along it).
    const json* f = r.find(o, "fibers");
    const std::string fp = key_path(path, "fibers");
    json fout = nullptr;
    if (f) {
      if (!f->is_object()) r.fail(fp, "must be an object, got " + type_desc(*f));
      r.object(*f, fp, {"type", "a1"});
      r.choice(*f, fp, "type", {"constant"}, 0);
      const Vec3d a1 = r.vec(*f, fp, "a1");
      r.check(a1.norm() > 0, key_path(fp, "a1"), "must be non-zero");
      spec->fibers.a1 = a1.normalized();
      fout = {{"type", "constant"}, {"a1", vec_json(a1, 3)}};
    } else {
      spec->fibers.a1 = Vec3d::Zero();  // each triangle's first edge
    }
    out["fibers"] = fout;
  }
  // The body's box: the centre of its angular velocity, and the scene's pictures.
  Vec3d lo = mesh.vertices[0], hi = lo;
  for (const Vec3d& x : mesh.vertices) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  spec->shape = Shape();
  spec->shape.dim = r.dim;
  spec->shape.type = Shape::Type::Box;
  spec->shape.min = lo, spec->shape.max = hi;
  spec->mesh = std::make_shared<const CodimMesh>(std::move(mesh));
  return out;
}

}  // namespace tear::scene_detail
