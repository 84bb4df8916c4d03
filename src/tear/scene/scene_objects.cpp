// "objects" and "boundaries" sections (SCENE_FORMAT.md).
#include "tear/io/atomic_file.h"
#include "tear/io/ply.h"
#include "tear/materials/registry.h"
#include "tear/scene/scene_parts.h"

#include <cmath>

namespace tear::scene_detail {

namespace {

// 2D: a scalar omega_z; 3D: a vector.
Vec3d angular_velocity(const Reader& r, const json& obj, const std::string& path, json* out) {
  Vec3d w = Vec3d::Zero();
  if (r.dim == 2) {
    w.z() = r.number(obj, path, "angular_velocity", 0.0);
    (*out)["angular_velocity"] = w.z();
  } else {
    w = r.vec(obj, path, "angular_velocity", Vec3d::Zero());
    (*out)["angular_velocity"] = vec_json(w, 3);
  }
  return w;
}

// Fiber field defaults: a1 = x, centre = the shape's world centre, axis = the shape's world
// axis for cylinders and tubes, else z (3D) or x (2D; only "longitudinal" uses it there).
json parse_fibers(const Reader& r, const json& obj, const std::string& opath, const Shape& shape,
                  FiberSpec* f) {
  static const json kEmpty = json::object();
  const json* j = r.find(obj, "fibers");
  if (!j) j = &kEmpty;
  std::string path = key_path(opath, "fibers");
  if (!j->is_object()) r.fail(path, "must be an object, got " + type_desc(*j));
  // The type first, so that a recognised but unimplemented field is named as such rather
  // than through its keys ("sources", "file").
  int type = r.choice(*j, path, "type",
                      {"constant", "radial", "circumferential", "longitudinal", "random", "flow",
                       "from_file"},
                      0);
  if (type == 5)
    r.object(*j, path, {"type", "a1", "a2", "sources", "sinks", "radius", "spread"});
  else
    r.object(*j, path, {"type", "a1", "a2", "center", "axis", "spread"});
  f->type = FiberField(type);
  const char* names[] = {"constant", "radial",   "circumferential", "longitudinal",
                         "random",   "flow",     "from_file"};
  json out = {{"type", names[int(f->type)]}};
  f->spread = r.number(*j, path, "spread", 0.0);
  r.check(f->spread >= 0 && f->spread <= 90, key_path(path, "spread"),
          "must be in [0, 90] degrees, got " + num_str(f->spread));
  out["spread"] = f->spread;

  Vec3d a1 = r.vec(*j, path, "a1", Vec3d::UnitX());
  r.check(a1.norm() > 0, key_path(path, "a1"), "must be non-zero");
  f->a1 = a1.normalized();
  out["a1"] = vec_json(a1, r.dim);
  out["a2"] = nullptr;
  f->has_a2 = r.find(*j, "a2") != nullptr;
  f->a2 = Vec3d::Zero();
  if (f->has_a2) {
    Vec3d a2 = r.vec(*j, path, "a2");
    r.check(a2.norm() > 0, key_path(path, "a2"), "must be non-zero");
    r.check(f->a1.cross(a2.normalized()).norm() > 1e-6, key_path(path, "a2"),
            "must not be parallel to a1");
    f->a2 = a2.normalized();
    out["a2"] = vec_json(a2, r.dim);
  }
  if (f->type == FiberField::Flow) {
    for (const char* key : {"sources", "sinks"}) {
      const std::string kp = key_path(path, key);
      const json* list = r.find(*j, key);
      if (!list) r.fail(kp, "required (an array of points)");
      if (!list->is_array() || list->empty())
        r.fail(kp, "must be a non-empty array of points, got " + type_desc(*list));
      std::vector<Vec3d>& points = key[1] == 'o' ? f->sources : f->sinks;
      json resolved = json::array();
      for (size_t k = 0; k < list->size(); ++k) {
        points.push_back(r.as_vec((*list)[k], index_path(kp, k), r.dim));
        resolved.push_back(vec_json(points.back(), r.dim));
      }
      out[key] = resolved;
    }
    f->flow_radius = r.number(*j, path, "radius", 0.0);
    r.check(f->flow_radius >= 0, key_path(path, "radius"),
            "must be > 0 (or 0 for two grid cells), got " + num_str(f->flow_radius));
    out["radius"] = f->flow_radius;
    return out;
  }
  f->center = r.vec(*j, path, "center", shape.world_center());
  out["center"] = vec_json(f->center, r.dim);
  Vec3d axis_def = r.dim == 3 ? Vec3d::UnitZ() : Vec3d::UnitX();
  if (shape.type == Shape::Type::Cylinder || shape.type == Shape::Type::Tube ||
      shape.type == Shape::Type::Cone || shape.type == Shape::Type::Torus ||
      (shape.type == Shape::Type::Wedge && r.dim == 3)) {
    axis_def = shape.transform.rotate * shape.axis;
    if (r.dim == 2) axis_def.z() = 0;
  }
  Vec3d axis = r.vec(*j, path, "axis", axis_def);
  r.check(axis.norm() > 0, key_path(path, "axis"), "must be non-zero");
  f->axis = axis.normalized();
  out["axis"] = vec_json(axis, r.dim);
  return out;
}

// A "particles" object's points from its PLY file (x y [z] and optional vx vy [vz], volume,
// material, fx fy [fz], f2x f2y [f2z]); its shape becomes their bounding box.
json parse_points(const Reader& r, const json& shape, const std::string& path, const Scene& scene,
                  ObjectSpec* spec) {
  r.object(shape, path, {"type", "file"});
  json out = {{"type", "particles"}};
  const std::string fp = key_path(path, "file");
  const std::string file = scene_file(r, shape, path, &out);
  PointTable t;
  try {
    t = decode_ply(read_file(file));
  } catch (const std::exception& e) {
    r.fail(fp, "'" + file + "': " + e.what());
  }
  auto bad = [&](const std::string& why) { r.fail(fp, "'" + file + "': " + why); };
  if (t.count == 0) bad("has no points");
  const int dim = r.dim;
  const char* axes[] = {"x", "y", "z"};
  // A vector column group (prefix + x, y[, z]): all of its dim columns, or none.
  auto vectors = [&](const std::string& prefix, const std::string& what) {
    std::vector<Vec3d> v;
    int present = 0;
    for (int d = 0; d < dim; ++d) present += t.has(prefix + axes[d]);
    if (present == 0) return v;
    if (present < dim)
      bad(what + " needs the columns " + prefix + "x, " + prefix + "y" +
          (dim == 3 ? ", " + prefix + "z" : "") + " (some are missing)");
    v.assign(t.count, Vec3d::Zero());
    for (int d = 0; d < dim; ++d) {
      const std::vector<double>& c = t.column(prefix + axes[d]);
      for (size_t i = 0; i < t.count; ++i) v[i][d] = c[i];
    }
    for (size_t i = 0; i < t.count; ++i)
      if (!v[i].allFinite()) bad(what + " of point " + std::to_string(i) + " is not finite");
    return v;
  };
  auto points = std::make_shared<PointSet>();
  points->x = vectors("", "the position");
  if (points->x.empty()) bad("has no x, y" + std::string(dim == 3 ? ", z" : "") + " columns");
  points->v = vectors("v", "the velocity");
  points->a1 = vectors("f", "the fiber a1");
  points->a2 = vectors("f2", "the fiber a2");
  for (size_t i = 0; i < t.count; ++i)
    for (int d = 0; d < dim; ++d)
      if (!(points->x[i][d] >= scene.domain_min[d] && points->x[i][d] <= scene.domain_max[d]))
        bad("point " + std::to_string(i) + " (" + num_str(points->x[i][0]) + ", " +
            num_str(points->x[i][1]) + (dim == 3 ? ", " + num_str(points->x[i][2]) : "") +
            ") is outside the grid domain");
  if (t.has("volume")) {
    points->volume = t.column("volume");
    for (size_t i = 0; i < t.count; ++i)
      if (!(points->volume[i] > 0))
        bad("the volume of point " + std::to_string(i) + " must be > 0, got " +
            num_str(points->volume[i]));
  }
  if (t.has("material")) {
    for (size_t i = 0; i < t.count; ++i) {
      const double m = t.column("material")[i];
      if (!(m >= 0 && m < double(scene.materials.size()) && m == std::floor(m)))
        bad("the material of point " + std::to_string(i) + " is " + num_str(m) +
            ", not the number of a material (0 to " + std::to_string(scene.materials.size() - 1) +
            ", in name order)");
      points->material.push_back(int(m));
    }
  }
  for (size_t i = 0; i < points->a1.size(); ++i)
    if (!(points->a1[i].norm() > 0)) bad("the fiber a1 of point " + std::to_string(i) + " is zero");
  // The shape: the points' bounding box (fiber field centres, angular velocity, pictures).
  Vec3d lo = points->x[0], hi = points->x[0];
  for (const Vec3d& x : points->x) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  spec->shape = Shape();
  spec->shape.dim = dim;
  spec->shape.type = Shape::Type::Box;
  spec->shape.min = lo, spec->shape.max = hi;
  spec->points = points;
  out["points"] = t.count;
  return out;
}

// objects[].regions: [{shape, material, fibers}], each region's fibers defaulting to the
// object's (the same field carries on into the region).
json parse_regions(const Reader& r, const json& o, const std::string& path, const Scene& scene,
                   const json& object_fibers, ObjectSpec* spec) {
  json out = json::array();
  const json* regions = r.find(o, "regions");
  if (!regions) return out;
  const std::string rp = key_path(path, "regions");
  if (!regions->is_array()) r.fail(rp, "must be an array of {shape, material}, got " + type_desc(*regions));
  for (size_t k = 0; k < regions->size(); ++k) {
    const json& g = (*regions)[k];
    const std::string gp = index_path(rp, k);
    if (!g.is_object()) r.fail(gp, "must be an object {shape, material}, got " + type_desc(g));
    r.object(g, gp, {"shape", "material", "fibers"});
    RegionSpec region;
    json gout;
    const json* sj = r.find(g, "shape");
    if (!sj) r.fail(key_path(gp, "shape"), "required");
    gout["shape"] = parse_shape(r, *sj, key_path(gp, "shape"), true, &region.shape);
    region.material = material_index(r, g, gp, scene, &gout);
    if (r.find(g, "fibers")) {
      gout["fibers"] = parse_fibers(r, g, gp, region.shape, &region.fibers);
      if (region.fibers.type == FiberField::Flow || region.fibers.type == FiberField::FromFile)
        r.fail(key_path(key_path(gp, "fibers"), "type"),
               "\"" + gout["fibers"]["type"].get<std::string>() +
                   "\" is for whole objects (give it to the object; regions inherit it)");
    } else {
      region.fibers = spec->fibers;
      gout["fibers"] = object_fibers;
    }
    spec->regions.push_back(region);
    out.push_back(gout);
  }
  return out;
}

json parse_object(const Reader& r, const json& o, const std::string& path, const Scene& scene,
                  size_t index, ObjectSpec* spec) {
  if (!o.is_object()) r.fail(path, "must be an object, got " + type_desc(o));
  spec->kind = ObjectKind(r.choice(o, path, "kind", {"volume", "surface", "curves"}, 0));
  if (spec->kind != ObjectKind::Volume) return parse_codim_object(r, o, path, scene, index, spec);
  r.object(o, path,
           {"kind", "simulation", "mesh_size", "initial_nodes", "mass", "shape", "material", "ppc",
            "sampling", "velocity", "angular_velocity", "fibers", "regions"});
  json out;
  out["kind"] = "volume";
  spec->fem = r.choice(o, path, "simulation", {"mpm", "fem"}, 0) == 1;
  out["simulation"] = spec->fem ? "fem" : "mpm";
  if (spec->fem) {
    spec->mesh_size = r.number(o, path, "mesh_size", scene.dx);
    r.check(spec->mesh_size > 0 && std::isfinite(spec->mesh_size), key_path(path, "mesh_size"),
            "must be a positive length, got " + num_str(spec->mesh_size));
    out["mesh_size"] = spec->mesh_size;
    spec->node_start =
        ObjectSpec::NodeStart(r.choice(o, path, "initial_nodes", {"rest", "random", "point"}, 0));
    const char* const starts[] = {"rest", "random", "point"};
    out["initial_nodes"] = starts[int(spec->node_start)];
    spec->consistent_mass = r.choice(o, path, "mass", {"lumped", "consistent"}, 0) == 1;
    out["mass"] = spec->consistent_mass ? "consistent" : "lumped";
  } else {
    for (const char* key : {"mesh_size", "initial_nodes", "mass"})
      if (r.find(o, key))
        r.fail(key_path(path, key), "is for \"simulation\": \"fem\" objects only");
  }
  const json* sj = r.find(o, "shape");
  if (!sj) r.fail(key_path(path, "shape"), "required");
  std::shared_ptr<const FemMesh> file_mesh;
  if (sj->is_object() && sj->contains("type") && (*sj)["type"] == "particles")
    out["shape"] = parse_points(r, *sj, key_path(path, "shape"), scene, spec);
  else
    out["shape"] = parse_shape(r, *sj, key_path(path, "shape"), false, &spec->shape,
                               spec->fem ? &file_mesh : nullptr);
  if (file_mesh) {
    // A volume mesh file: its elements are the body's, placed by the shape's transform.
    if (r.find(o, "mesh_size"))
      r.fail(key_path(path, "mesh_size"),
             "is for shapes that netgen meshes: the elements of the mesh file " +
                 out["shape"]["file"].get<std::string>() + " are used as they are");
    out.erase("mesh_size");
    auto placed = std::make_shared<FemMesh>(*file_mesh);
    for (Vec3d& x : placed->nodes) {
      x = spec->shape.transform.to_world(x);
      if (r.dim == 2) x.z() = 0;
    }
    spec->mesh_size = mesh_figures(*placed).mean_edge;
    spec->fem_mesh = std::move(placed);
  }
  // Particles are kept only inside the grid domain: a shape wholly outside it samples nothing.
  Vec3d lo, hi;
  spec->shape.bounds(&lo, &hi);
  for (int i = 0; i < r.dim; ++i)
    r.check(hi[i] > scene.domain_min[i] && lo[i] < scene.domain_max[i], key_path(path, "shape"),
            "lies outside the grid domain along axis " + std::to_string(i) + " (shape spans [" +
                num_str(lo[i]) + ", " + num_str(hi[i]) + "], domain [" +
                num_str(scene.domain_min[i]) + ", " + num_str(scene.domain_max[i]) + "])");

  if (spec->fem) {
    const Shape::Type t = spec->shape.type;
    const bool meshable = t == Shape::Type::Box || t == Shape::Type::Sphere ||
                          t == Shape::Type::Cylinder || t == Shape::Type::Mesh;
    if (spec->points || !meshable)
      r.fail(key_path(path, "shape"),
             std::string("an FEM body is meshed from a box, sphere, cylinder or mesh") +
                 (r.dim == 3 ? "" : " (a triangle mesh file)") + " shape (docs/fem.md), got " +
                 (spec->points ? std::string("particles") : out["shape"].value("type", "?")));
  }
  spec->material = material_index(r, o, path, scene, &out);
  const Model model = scene.materials[size_t(spec->material)].params.model;
  if (spec->fem) {
    const MaterialSpec& m = scene.materials[size_t(spec->material)];
    if (m.inextensibility.enabled)
      r.fail(key_path(path, "material"), "material \"" + m.name +
                                             "\" has inextensibility, which FEM bodies do not "
                                             "take yet (docs/fem.md)");
  }
  if (!spec->fem) {
    const MaterialSpec& m = scene.materials[size_t(spec->material)];
    r.check(m.rayleigh_alpha == 0 && m.rayleigh_beta == 0, key_path(path, "material"),
            "material \"" + m.name + "\" has Rayleigh damping (rayleigh), which only FEM bodies "
            "take (\"simulation\": \"fem\"; docs/fem.md)");
  }
  if (model_codimension(model) != 0)
    r.fail(key_path(path, "material"),
           "material \"" + out["material"].get<std::string>() + "\" is " + model_name(model) +
               ", a model for " + (model_codimension(model) == 2 ? "surfaces" : "curves") +
               ": give the object \"kind\": \"" +
               (model_codimension(model) == 2 ? "surface" : "curves") + "\" and a mesh shape");

  long long ppc = r.integer(o, path, "ppc", default_ppc(r.dim));
  r.check(ppc >= 1 && ppc <= 4096, key_path(path, "ppc"),
          "must be in [1, 4096], got " + std::to_string(ppc));
  spec->ppc = int(ppc);
  out["ppc"] = spec->ppc;
  spec->grid_sampling = r.choice(o, path, "sampling", {"random", "grid"}, 0) == 1;
  if (spec->grid_sampling && ppc_root(spec->ppc, r.dim) == 0)
    r.fail(key_path(path, "ppc"), "must be a perfect " +
                                      std::string(r.dim == 2 ? "square" : "cube") +
                                      " with \"sampling\": \"grid\", got " + std::to_string(ppc));
  out["sampling"] = spec->grid_sampling ? "grid" : "random";
  spec->velocity = r.vec(o, path, "velocity", Vec3d::Zero());
  out["velocity"] = vec_json(spec->velocity, r.dim);
  spec->angular_velocity = angular_velocity(r, o, path, &out);
  out["fibers"] = parse_fibers(r, o, path, spec->shape, &spec->fibers);
  if (spec->fibers.type == FiberField::FromFile && (!spec->points || spec->points->a1.empty()))
    r.fail(key_path(key_path(path, "fibers"), "type"),
           "\"from_file\" needs a \"particles\" shape whose file has the columns fx, fy" +
               std::string(r.dim == 3 ? ", fz" : "") + " (and f2x, f2y" +
               (r.dim == 3 ? ", f2z" : "") + " for a second fiber)");
  if (spec->fem && (spec->fibers.type == FiberField::Flow ||
                    spec->fibers.type == FiberField::FromFile))
    r.fail(key_path(key_path(path, "fibers"), "type"),
           "FEM bodies take constant, radial, circumferential, longitudinal or random fibers");
  out["regions"] = parse_regions(r, o, path, scene, out["fibers"], spec);
  return out;
}

json parse_boundary(const Reader& r, const json& b, const std::string& path, Collider* spec) {
  r.object(b, path,
           {"type", "shape", "friction", "velocity", "angular_velocity", "start", "end"});
  const char* types[] = {"sticky", "slip", "separate"};
  spec->type = ContactType(r.choice(b, path, "type", {"sticky", "slip", "separate"}));
  json out = {{"type", types[int(spec->type)]}};
  const json* sj = r.find(b, "shape");
  if (!sj) r.fail(key_path(path, "shape"), "required");
  out["shape"] = parse_shape(r, *sj, key_path(path, "shape"), true, &spec->shape);
  spec->friction = r.number(b, path, "friction", 0.0);
  r.non_negative(spec->friction, key_path(path, "friction"));
  out["friction"] = spec->friction;
  spec->velocity = r.vec(b, path, "velocity", Vec3d::Zero());
  out["velocity"] = vec_json(spec->velocity, r.dim);
  spec->angular_velocity = angular_velocity(r, b, path, &out);
  spec->start = r.number(b, path, "start", 0.0);
  spec->end = r.number(b, path, "end", 1e30);
  r.check(spec->end > spec->start, key_path(path, "end"),
          "must be > start (" + num_str(spec->start) + "), got " + num_str(spec->end));
  out["start"] = spec->start;
  out["end"] = spec->end;
  return out;
}

const json* array_section(const Reader& r, const json& doc, const char* key) {
  const json* a = r.find(doc, key);
  if (a && !a->is_array()) r.fail(key, "must be an array, got " + type_desc(*a));
  return a;
}

}  // namespace

int material_index(const Reader& r, const json& obj, const std::string& path, const Scene& scene,
                   json* out) {
  std::string mat = r.string(obj, path, "material");
  (*out)["material"] = mat;
  for (size_t i = 0; i < scene.materials.size(); ++i)
    if (scene.materials[i].name == mat) return int(i);
  std::string list;
  for (const MaterialSpec& m : scene.materials) list += (list.empty() ? "" : ", ") + m.name;
  r.fail(key_path(path, "material"),
         "unknown material \"" + mat + "\" (defined: " + (list.empty() ? "none" : list) + ")");
}

json parse_objects(const Reader& r, const json& doc, Scene* scene) {
  json out = json::array();
  const json* objs = array_section(r, doc, "objects");
  if (!objs) r.fail("objects", "required");
  for (size_t i = 0; i < objs->size(); ++i) {
    ObjectSpec spec;
    out.push_back(parse_object(r, (*objs)[i], index_path("objects", i), *scene, i, &spec));
    scene->objects.push_back(spec);
  }
  return out;
}

json parse_boundaries(const Reader& r, const json& doc, Scene* scene) {
  json out = json::array();
  const json* bs = array_section(r, doc, "boundaries");
  if (!bs) return out;
  for (size_t i = 0; i < bs->size(); ++i) {
    Collider spec;
    out.push_back(parse_boundary(r, (*bs)[i], index_path("boundaries", i), &spec));
    scene->boundaries.push_back(spec);
  }
  return out;
}

}  // namespace tear::scene_detail
