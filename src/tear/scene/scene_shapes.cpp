// Shape descriptions: "objects[].shape" and "boundaries[].shape" (SCENE_FORMAT.md).
// Transform convention: x_world = translate + R (scale x_local). R is, in 2D, a rotation by
// "rotate" degrees counter-clockwise about z; in 3D, "rotate": {"axis": [x,y,z], "angle_deg": a}
// (right-handed axis-angle).
#include "tear/fem/mesh.h"
#include "tear/geometry/shape.h"
#include "tear/io/mesh_io.h"
#include "tear/io/volume_mesh.h"
#include "tear/scene/scene_parts.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <optional>

namespace tear::scene_detail {

namespace {

constexpr double kPi = 3.14159265358979323846;

}  // namespace

json parse_transform(const Reader& r, const json& shape, const std::string& path,
                     ShapeTransform* t) {
  static const json kEmpty = json::object();
  const json* j = r.find(shape, "transform");
  if (!j) j = &kEmpty;
  std::string p = key_path(path, "transform");
  r.object(*j, p, {"translate", "rotate", "scale"});
  t->translate = r.vec(*j, p, "translate", Vec3d::Zero());
  t->scale = r.number(*j, p, "scale", 1.0);
  r.positive(t->scale, key_path(p, "scale"));
  json out = {{"translate", vec_json(t->translate, r.dim)}, {"scale", t->scale}};
  std::string rp = key_path(p, "rotate");
  if (r.dim == 2) {
    double deg = r.number(*j, p, "rotate", 0.0);
    t->rotate = Eigen::AngleAxisd(deg * kPi / 180, Vec3d::UnitZ()).toRotationMatrix();
    out["rotate"] = deg;
  } else {
    static const json kNoRotation = {{"axis", {0.0, 0.0, 1.0}}, {"angle_deg", 0.0}};
    const json* rot = r.find(*j, "rotate");
    if (!rot) rot = &kNoRotation;
    if (!rot->is_object())
      r.fail(rp, "must be {\"axis\": [x, y, z], \"angle_deg\": a} in 3D, got " + type_desc(*rot));
    r.object(*rot, rp, {"axis", "angle_deg"});
    Vec3d axis = r.vec(*rot, rp, "axis");
    r.check(axis.norm() > 0, key_path(rp, "axis"), "must be non-zero");
    double deg = r.number(*rot, rp, "angle_deg");
    t->rotate = Eigen::AngleAxisd(deg * kPi / 180, axis.normalized()).toRotationMatrix();
    out["rotate"] = {{"axis", vec_json(axis, 3)}, {"angle_deg", deg}};
  }
  return out;
}

namespace {

// A unit axis (rejecting zero) read from obj[key].
Vec3d unit_vec(const Reader& r, const json& obj, const std::string& path, const char* key,
               json* out) {
  Vec3d a = r.vec(obj, path, key);
  r.check(a.norm() > 0, key_path(path, key), "must be non-zero");
  (*out)[key] = vec_json(a, r.dim);
  return a.normalized();
}

double positive_number(const Reader& r, const json& obj, const std::string& path,
                       const char* key, json* out) {
  double v = r.number(obj, path, key);
  r.positive(v, key_path(path, key));
  (*out)[key] = v;
  return v;
}

// Whether `file` is a volume mesh (tetrahedra or 2D triangles) by its extension: gmsh .msh,
// TetGen .node/.ele, VTU.
bool volume_mesh_file(const std::string& file) {
  std::string ext = std::filesystem::path(file).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  return ext == ".msh" || ext == ".node" || ext == ".ele" || ext == ".vtu";
}

// The solid a volume mesh fills, for the inside and distance tests of every other use of the
// shape: 3D, the closed surface of its boundary faces; 2D, a prism over the triangles (caps at
// z = +-Z, sides on the boundary edges), whose z = 0 section is the mesh, with Z large enough
// that a cap is never nearer than a side to a point of the plane near the mesh.
std::shared_ptr<const MeshSolid> solid_of(const FemMesh& m, const std::string& name) {
  std::vector<Vec3d> points = m.nodes;
  std::vector<std::array<int, 3>> triangles;
  if (m.dim == 3) {
    triangles = boundary_faces(m);
  } else {
    Vec3d lo = m.nodes[0], hi = m.nodes[0];
    for (const Vec3d& x : m.nodes) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
    const double z = 10 * (hi - lo).norm();
    const int n = int(m.nodes.size());
    points.resize(2 * m.nodes.size());
    for (size_t i = 0; i < m.nodes.size(); ++i) {
      points[i] = m.nodes[i] - z * Vec3d::UnitZ();
      points[i + m.nodes.size()] = m.nodes[i] + z * Vec3d::UnitZ();
    }
    for (const std::array<int, 4>& t : m.elements) {
      triangles.push_back({t[0], t[2], t[1]});               // bottom, facing -z
      triangles.push_back({t[0] + n, t[1] + n, t[2] + n});   // top, facing +z
    }
    for (const std::array<int, 3>& e : boundary_faces(m)) {  // the body on the left of e0 - e1
      triangles.push_back({e[0], e[1], e[1] + n});
      triangles.push_back({e[0], e[1] + n, e[0] + n});
    }
  }
  return std::make_shared<const MeshSolid>(points, triangles, name);
}

// A "mesh" shape's volume mesh file, read and checked as an FEM mesh (check_fem_mesh: the
// element and the reason), in the shape's local frame. A file whose elements are all the other
// way round (a mirrored convention) is turned; a mix is refused at its first inverted element.
std::shared_ptr<const FemMesh> read_volume_file(const Reader& r, const std::string& file,
                                                const std::string& fp) {
  VolumeMesh v;
  try {
    v = read_volume_mesh(file);
  } catch (const std::exception& e) {
    r.fail(fp, e.what());
  }
  const std::string quoted = "'" + file + "'";
  if (v.dim != r.dim)
    r.fail(fp, quoted + (v.dim == 3
                             ? " holds tetrahedra: a 2D scene takes a mesh of triangles"
                             : " holds triangles only (a 2D mesh): a 3D scene takes tetrahedra, or "
                               "a closed surface as OBJ, PLY or STL"));
  auto m = std::make_shared<FemMesh>();
  m->dim = v.dim;
  m->nodes.reserve(v.nodes.size());
  for (const std::array<double, 3>& x : v.nodes) m->nodes.emplace_back(x[0], x[1], x[2]);
  m->elements.reserve(v.cells.size());
  for (const std::array<uint32_t, 4>& c : v.cells)
    m->elements.push_back({int(c[0]), int(c[1]), int(c[2]), v.dim == 3 ? int(c[3]) : -1});
  bool all_inverted = true;
  for (size_t e = 0; e < m->elements.size() && all_inverted; ++e)
    all_inverted = element_volume(*m, e) < 0;
  if (all_inverted) orient_elements(m.get());
  try {
    check_fem_mesh(*m, quoted);
  } catch (const std::exception& e) {
    r.fail(fp, e.what());
  }
  return m;
}

// The closed mesh of a "mesh" shape: "file" is relative to the scene file's folder; the
// resolved scene keeps its absolute path. A surface (OBJ, PLY, STL; 3D only) is the solid's
// boundary; a volume mesh (volume_mesh_file) is the solid itself, returned in *volume too when
// it is asked for (FEM bodies take its elements as they are).
std::shared_ptr<const MeshSolid> read_mesh(const Reader& r, const json& j, const std::string& path,
                                           json* out, std::shared_ptr<const FemMesh>* volume) {
  const std::string fp = key_path(path, "file");
  const std::string file = scene_file(r, j, path, out);
  if (volume_mesh_file(file)) {
    std::shared_ptr<const FemMesh> m = read_volume_file(r, file, fp);
    if (volume) *volume = m;
    try {
      return solid_of(*m, "mesh '" + file + "'");
    } catch (const std::exception& e) {
      r.fail(fp, "'" + file + "': its boundary " + e.what());
    }
  }
  if (r.dim != 3)
    r.fail(fp, "a 2D scene's \"mesh\" is a triangle mesh file (.msh, .node/.ele or .vtu), not '" +
                   file + "' (OBJ, PLY and STL surfaces need dim 3)");
  TriMesh mesh;
  try {
    mesh = read_mesh_file(file);
  } catch (const std::exception& e) {
    r.fail(fp, e.what());
  }
  std::vector<Vec3d> vertices(mesh.vertices.size());
  for (size_t v = 0; v < vertices.size(); ++v) vertices[v] = mesh.vertices[v].cast<double>();
  try {
    return std::make_shared<const MeshSolid>(vertices, mesh.triangles, "mesh '" + file + "'");
  } catch (const std::exception& e) {
    r.fail(fp, "'" + file + "' " + e.what());
  }
}

}  // namespace

std::string scene_file(const Reader& r, const json& j, const std::string& path, json* out) {
  namespace fs = std::filesystem;
  const std::string name = r.string(j, path, "file");
  r.check(!name.empty(), key_path(path, "file"), "must name a file");
  fs::path file(name);
  if (file.is_relative()) file = fs::absolute(fs::path(r.file()).parent_path() / file);
  file = file.lexically_normal();
  (*out)["file"] = file.string();
  return file.string();
}

namespace {

// An entry pair [bottom, top] (or one number for both) at obj[key]; `def` when absent.
std::array<double, 2> end_pair(const Reader& r, const json& obj, const std::string& path,
                               const char* key, std::optional<double> def) {
  const json* v = r.find(obj, key);
  const std::string p = key_path(path, key);
  if (!v) {
    if (!def) r.fail(p, "required");
    return {*def, *def};
  }
  if (!v->is_array()) {
    const double x = r.as_number(*v, p);
    return {x, x};
  }
  if (v->size() != 2)
    r.fail(p, "must be a number or [bottom, top], got " + entries(v->size()));
  return {r.as_number((*v)[0], key_path(p, "0")), r.as_number((*v)[1], key_path(p, "1"))};
}

// cone, torus and wedge: their keys, checked, into s and the resolved `out`.
void parse_round_shape(const Reader& r, const json& j, const std::string& path, Shape* s,
                       json* out) {
  s->center = r.vec(j, path, "center");
  (*out)["center"] = vec_json(s->center, r.dim);
  if (s->type != Shape::Type::Wedge || r.dim == 3) s->axis = unit_vec(r, j, path, "axis", out);
  if (s->type == Shape::Type::Cone) {
    s->height = positive_number(r, j, path, "height", out);
    const auto outer = end_pair(r, j, path, "radius", std::nullopt);
    const auto inner = end_pair(r, j, path, "inner_radius", 0.0);
    for (int e = 0; e < 2; ++e) {
      const std::string end = e == 0 ? "bottom" : "top";
      r.check(outer[size_t(e)] > 0, key_path(path, "radius"),
              "must be > 0 at both ends, got " + num_str(outer[size_t(e)]) + " at the " + end);
      r.check(inner[size_t(e)] >= 0 && inner[size_t(e)] < outer[size_t(e)],
              key_path(path, "inner_radius"),
              "must be in [0, radius) at both ends, got " + num_str(inner[size_t(e)]) +
                  " at the " + end + " (radius " + num_str(outer[size_t(e)]) + ")");
    }
    s->radius = outer[0], s->radius_top = outer[1];
    s->inner_radius = inner[0], s->inner_radius_top = inner[1];
    (*out)["radius"] = {outer[0], outer[1]};
    (*out)["inner_radius"] = {inner[0], inner[1]};
  } else if (s->type == Shape::Type::Torus) {
    s->radius = positive_number(r, j, path, "radius", out);
    s->tube_radius = positive_number(r, j, path, "tube_radius", out);
    r.check(s->tube_radius < s->radius, key_path(path, "tube_radius"),
            "must be < radius = " + num_str(s->radius) + " (a torus with a hole), got " +
                num_str(s->tube_radius));
  } else {
    s->radius = positive_number(r, j, path, "radius", out);
    s->inner_radius = r.number(j, path, "inner_radius", 0.0);
    r.check(s->inner_radius >= 0 && s->inner_radius < s->radius, key_path(path, "inner_radius"),
            "must be in [0, radius = " + num_str(s->radius) + "), got " + num_str(s->inner_radius));
    (*out)["inner_radius"] = s->inner_radius;
    const double deg = r.number(j, path, "angle_deg");
    r.check(deg > 0 && deg <= 180, key_path(path, "angle_deg"),
            "must be in (0, 180] degrees, got " + num_str(deg));
    s->angle = deg * kPi / 180;
    (*out)["angle_deg"] = deg;
    const Vec3d axis = r.dim == 3 ? s->axis : Vec3d::UnitZ();
    if (r.dim == 2) s->axis = axis;
    const Vec3d dir = r.vec(j, path, "direction");
    r.check((dir - dir.dot(axis) * axis).norm() > 1e-9 * dir.norm(), key_path(path, "direction"),
            "must not be parallel to the axis (it points to the middle of the wedge)");
    s->direction = dir;
    (*out)["direction"] = vec_json(dir, r.dim);
  }
}

}  // namespace

json parse_shape(const Reader& r, const json& j, const std::string& path, bool allow_half_space,
                 Shape* s, std::shared_ptr<const FemMesh>* volume) {
  if (!j.is_object()) r.fail(path, "must be an object, got " + type_desc(j));
  // In Shape::Type's order; "particles" last.
  int type = r.choice(j, path, "type",
                      {"box", "sphere", "cylinder", "tube", "half_space", "mesh", "cone", "torus",
                       "wedge", "particles"});
  std::string tp = key_path(path, "type");
  if (type == 9)
    r.fail(tp, allow_half_space ? "\"particles\" is only for objects (a collider needs a surface)"
                                : "\"particles\" is read by the object, not as a shape");
  if (type == 4 && !allow_half_space)
    r.fail(tp, "\"half_space\" is only allowed for boundaries (objects must be bounded)");
  switch (type) {
    case 0: r.object(j, path, {"type", "min", "max", "transform"}); break;
    case 1: r.object(j, path, {"type", "center", "radius", "transform"}); break;
    case 2: r.object(j, path, {"type", "center", "axis", "radius", "height", "transform"}); break;
    case 3:
      r.object(j, path,
               {"type", "center", "axis", "radius", "inner_radius", "height", "transform"});
      break;
    case 5: r.object(j, path, {"type", "file", "transform"}); break;
    case 6:
      r.object(j, path,
               {"type", "center", "axis", "radius", "inner_radius", "height", "transform"});
      break;
    case 7: r.object(j, path, {"type", "center", "axis", "radius", "tube_radius", "transform"}); break;
    case 8:
      if (r.dim == 3)
        r.object(j, path,
                 {"type", "center", "axis", "direction", "radius", "inner_radius", "angle_deg",
                  "transform"});
      else
        r.object(j, path,
                 {"type", "center", "direction", "radius", "inner_radius", "angle_deg", "transform"});
      break;
    default: r.object(j, path, {"type", "point", "normal", "transform"}); break;
  }
  *s = Shape();
  s->dim = r.dim;
  s->type = Shape::Type(type);
  json out = {{"type", j["type"]}};
  if (type == 0) {
    s->min = r.vec(j, path, "min");
    s->max = r.vec(j, path, "max");
    for (int i = 0; i < r.dim; ++i)
      r.check(s->min[i] < s->max[i], key_path(path, "max"),
              "must be > min in every entry (entry " + std::to_string(i) + ": " +
                  num_str(s->max[i]) + " <= " + num_str(s->min[i]) + ")");
    out["min"] = vec_json(s->min, r.dim);
    out["max"] = vec_json(s->max, r.dim);
  } else if (type <= 3) {
    s->center = r.vec(j, path, "center");
    out["center"] = vec_json(s->center, r.dim);
    if (type >= 2) s->axis = unit_vec(r, j, path, "axis", &out);
    s->radius = positive_number(r, j, path, "radius", &out);
    if (type >= 2) s->height = positive_number(r, j, path, "height", &out);
    if (type == 3) {
      s->inner_radius = r.number(j, path, "inner_radius");
      r.check(s->inner_radius >= 0 && s->inner_radius < s->radius,
              key_path(path, "inner_radius"),
              "must be in [0, radius = " + num_str(s->radius) + "), got " +
                  num_str(s->inner_radius));
      out["inner_radius"] = s->inner_radius;
    }
  } else if (type == 5) {
    s->mesh = read_mesh(r, j, path, &out, volume);
  } else if (type >= 6) {
    parse_round_shape(r, j, path, s, &out);
  } else {
    s->point = r.vec(j, path, "point");
    out["point"] = vec_json(s->point, r.dim);
    s->normal = unit_vec(r, j, path, "normal", &out);
  }
  out["transform"] = parse_transform(r, j, path, &s->transform);
  return out;
}

}  // namespace tear::scene_detail
