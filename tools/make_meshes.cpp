// make_meshes: the closed meshes of examples/meshes/ (docs/meshes.md), made by tear itself so
// that no example needs a download. Each object is an implicit solid (implicit_shapes.h: smooth
// unions of spheres, ellipsoids, capsules, boxes, or tear's own analytic shapes) meshed by
// surface/'s mesh_implicit (OpenVDB volumeToMesh, adaptive where the surface is flat). The
// coordinates are rounded to 1e-4 (short OBJ lines) and every mesh is checked as a scene would
// check it (MeshSolid: closed, 2-manifold, consistently oriented) before it is written.
//
// Usage: make_meshes OUT_DIR [--threads N] [NAME ...]   (default: every mesh)
// Prints one Markdown table row per mesh (docs/meshes.md). The same bytes for any thread count.
//
// Units: every object is 0.3-0.85 across, for scenes in a unit-sized domain, placed about the
// origin (move it with a shape transform), z up; docs/meshes.md lists the bounding boxes.
#include "implicit_shapes.h"

#include "tear/exec/threads.h"
#include "tear/geometry/mesh_solid.h"
#include "tear/io/atomic_file.h"
#include "tear/io/mesh_io.h"
#include "tear/surface/mesher.h"

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace tear {
namespace {

using namespace implicit;

struct MeshSpec {
  const char* name;
  Sdf sdf;
  Vec3d lo, hi;       // a box holding the solid with a voxel to spare
  double voxel;       // the grid the surface is taken from
  double adaptivity;  // OpenVDB's: 0 uniform triangles, towards 1 fewer where flat
};

constexpr double kRound = 1e-4;  // written coordinates are multiples of this

// A steak: a slab with rounded edges whose top is a low dome (a sphere cap), 0.13 thick in the
// middle and 0.07 at the corners.
Sdf meat_slab() {
  const Sdf slab = rounded_box(Vec3d::Zero(), Vec3d(0.4, 0.25, 0.07), 0.04);
  // The dome's sphere passes through the top centre (0, 0, 0.07) and the corners' z = 0.
  const double R = (0.4 * 0.4 + 0.25 * 0.25 + 0.07 * 0.07) / (2 * 0.07);
  return intersect(slab, sphere(Vec3d(0, 0, 0.07 - R), R), 0.03);
}

// An orange segment: the part of a ball of radius 0.35 about the origin between two planes
// through the z axis 40 degrees apart, centred on +x, its edges rounded over 1 cm.
constexpr double kOrangeRadius = 0.35, kPeel = 0.04, kPulpOverhang = 0.01, kOrangeRounding = 0.01;

// The two cut faces' half-space (a wedge of a ball much larger than the orange), its apex at
// x = apex on the x axis.
Sdf orange_faces(double apex) {
  Shape s;
  s.type = Shape::Type::Wedge;
  s.center = Vec3d(apex, 0, 0), s.axis = Vec3d::UnitZ(), s.direction = Vec3d::UnitX();
  s.radius = 1, s.angle = 40 * M_PI / 180;
  return shape(s);
}

Sdf orange_slice() {
  return intersect(sphere(Vec3d::Zero(), kOrangeRadius), orange_faces(0), kOrangeRounding);
}

// The pulp of orange_slice: inside the peel (radius 0.35 - 0.04), and reaching kPulpOverhang
// past the slice's two cut faces, so that as a region of the slice it takes in every particle
// of the cut faces and leaves the peel on the round side only. The faces move out by the
// overhang when the apex moves back along -x by overhang / sin(20 degrees).
Sdf orange_pulp() {
  return intersect(sphere(Vec3d::Zero(), kOrangeRadius - kPeel),
                   orange_faces(-kPulpOverhang / std::sin(20 * M_PI / 180)), kOrangeRounding);
}

// A fish facing +x, back up: an ellipsoid body narrowing into the tail's stalk, a forked tail
// of two flat lobes, a dorsal, an anal and two pectoral fins (fins 0.02-0.024 thick).
Sdf fish() {
  const Vec3d y = Vec3d::UnitY(), z = Vec3d::UnitZ();
  std::vector<Sdf> parts = {
      ellipsoid(Vec3d(0.04, 0, 0), Vec3d(0.28, 0.065, 0.12)),                          // body
      round_cone(Vec3d(-0.16, 0, 0), Vec3d(-0.3, 0, 0), 0.05, 0.018),                  // stalk
      ellipsoid(Vec3d(-0.345, 0, 0.06), Vec3d(0.09, 0.012, 0.03), rotation(y, 53)),    // tail
      ellipsoid(Vec3d(-0.345, 0, -0.06), Vec3d(0.09, 0.012, 0.03), rotation(y, -53)),  // tail
      ellipsoid(Vec3d(-0.01, 0, 0.125), Vec3d(0.11, 0.012, 0.06), rotation(y, -18)),   // dorsal
      ellipsoid(Vec3d(-0.13, 0, -0.095), Vec3d(0.06, 0.012, 0.035), rotation(y, 25)),  // anal
  };
  for (const double side : {-1.0, 1.0})  // pectoral fins, swept back and out
    parts.push_back(ellipsoid(Vec3d(0.12, side * 0.06, -0.04), Vec3d(0.06, 0.01, 0.025),
                              rotation(z, side * 25) * rotation(y, 20)));
  return smooth_union(std::move(parts), 0.02);
}

// Taubin's heart (x^2 + 9/4 y^2 + z^2 - 1)^3 = x^2 z^3 + 9/80 y^2 z^3, written with a cube
// root, x^2 + 9/4 y^2 + z^2 - 1 = cbrt(x^2 + 9/80 y^2) z, so that its gradient does not vanish
// on the surface; scaled by 0.3: 0.68 wide (x), 0.41 deep (y), 0.66 tall (z).
Sdf heart() {
  const double s = 0.3;
  return first_order_distance(
      [s](const Vec3d& p) {
        const Vec3d q = p / s;
        const double x2 = q.x() * q.x(), y2 = q.y() * q.y();
        return s * (x2 + 2.25 * y2 + q.z() * q.z() - 1 - std::cbrt(x2 + 0.1125 * y2) * q.z());
      },
      1e-4);
}

// A femur standing along z, 0.8 long: the shaft, flaring at both ends; at the top the ball of
// the head on its neck (towards -x) and the greater and lesser trochanters; at the bottom the
// two condyles.
Sdf femur() {
  return smooth_union({round_cone(Vec3d(0, 0, -0.26), Vec3d(0, 0, 0.26), 0.042, 0.038),
                       round_cone(Vec3d(0, 0, -0.2), Vec3d(0, 0.005, -0.31), 0.04, 0.07),
                       ellipsoid(Vec3d(0.045, 0.012, -0.33), Vec3d(0.05, 0.065, 0.06)),
                       ellipsoid(Vec3d(-0.045, 0.012, -0.33), Vec3d(0.05, 0.065, 0.06)),
                       round_cone(Vec3d(0, 0, 0.2), Vec3d(0.01, 0, 0.3), 0.04, 0.05),
                       round_cone(Vec3d(0, 0, 0.29), Vec3d(-0.085, 0, 0.345), 0.04, 0.032),
                       sphere(Vec3d(-0.1, 0, 0.355), 0.055),
                       ellipsoid(Vec3d(0.045, 0, 0.31), Vec3d(0.04, 0.04, 0.055)),
                       sphere(Vec3d(-0.03, 0.015, 0.22), 0.022)},
                      0.03);
}

// A toy armadillo standing on its hind legs, facing +x: body, head with a long snout and two
// tall ears, arms, legs with flat feet, and a tail reaching back to the ground.
Sdf armadillo() {
  const Vec3d x = Vec3d::UnitX();
  // The armour on the back: an ellipsoid banded by ridges 0.055 apart, 0.007 high.
  const Sdf shell = ellipsoid(Vec3d(-0.035, 0, 0.03), Vec3d(0.11, 0.135, 0.17));
  const Sdf banded = [shell](const Vec3d& p) {
    return shell(p) - 0.0035 * (1 + std::cos(2 * M_PI * (p.z() - 0.03) / 0.055));
  };
  std::vector<Sdf> parts = {
      ellipsoid(Vec3d(0, 0, 0), Vec3d(0.12, 0.14, 0.19)),                     // body
      banded,                                                                 // shell
      ellipsoid(Vec3d(0.04, 0, 0.26), Vec3d(0.08, 0.07, 0.075)),              // head
      round_cone(Vec3d(0.08, 0, 0.25), Vec3d(0.19, 0, 0.22), 0.05, 0.022),    // snout
      round_cone(Vec3d(-0.1, 0, -0.12), Vec3d(-0.3, 0, -0.33), 0.05, 0.018),  // tail
  };
  for (const double side : {-1.0, 1.0}) {
    const Vec3d m(1, side, 1);  // mirror through y = 0
    parts.push_back(ellipsoid(Vec3d(-0.01, 0.07, 0.37).cwiseProduct(m), Vec3d(0.018, 0.045, 0.085),
                              rotation(x, side * 25)));  // ear
    parts.push_back(round_cone(Vec3d(0.02, 0.12, 0.1).cwiseProduct(m),
                               Vec3d(0.11, 0.17, -0.02).cwiseProduct(m), 0.038, 0.03));  // arm
    parts.push_back(sphere(Vec3d(0.12, 0.175, -0.04).cwiseProduct(m), 0.035));           // hand
    parts.push_back(round_cone(Vec3d(0, 0.08, -0.12).cwiseProduct(m),
                               Vec3d(0.05, 0.1, -0.25).cwiseProduct(m), 0.065, 0.05));  // thigh
    parts.push_back(round_cone(Vec3d(0.05, 0.1, -0.25).cwiseProduct(m),
                               Vec3d(0, 0.1, -0.34).cwiseProduct(m), 0.05, 0.04));  // shin
    parts.push_back(
        ellipsoid(Vec3d(0.04, 0.1, -0.37).cwiseProduct(m), Vec3d(0.075, 0.045, 0.03)));  // foot
  }
  return smooth_union(std::move(parts), 0.03);
}

// A tapered tube along z (paper Fig. 3): 0.6 tall, outer radius 0.2 at the bottom and 0.12 at
// the top, walls 0.05 thick, the rims rounded over kRim. Its wall's section (r, z) is a
// trapezoid: rounded, it is the trapezoid shrunk by kRim, grown back by kRim. Shrinking moves the
// ends in by kRim and the slanted sides by kRim normal to themselves: the radius at a height by
// kRim / cos(slope).
Sdf tapered_tube() {
  constexpr double kHeight = 0.6, kRim = 0.01;
  const double bottom[2] = {0.15, 0.2}, top[2] = {0.07, 0.12};  // inner, outer radius
  const double slope = (bottom[1] - top[1]) / kHeight, shift = kRim * std::sqrt(1 + slope * slope);
  const double end = kHeight / 2 - kRim;  // the shrunk ends' height
  auto radius = [&](int k, double z) { return (bottom[k] + top[k]) / 2 - slope * z; };
  Shape s;
  s.type = Shape::Type::Cone;
  s.axis = Vec3d::UnitZ(), s.height = 2 * end;
  s.inner_radius = radius(0, -end) + shift, s.radius = radius(1, -end) - shift;
  s.inner_radius_top = radius(0, end) + shift, s.radius_top = radius(1, end) - shift;
  return [s](const Vec3d& p) { return s.sdf(p) - kRim; };
}

// A ring torus about z: radius 0.3 to the tube's centre circle, tube radius 0.1.
Sdf torus() {
  Shape s;
  s.type = Shape::Type::Torus;
  s.axis = Vec3d::UnitZ(), s.radius = 0.3, s.tube_radius = 0.1;
  return shape(s);
}

// Voxels and adaptivity chosen to keep each file under 150 KB and the thinnest parts (fins,
// ears, peel) several voxels across. Adaptive facets span several voxels and cut a little
// inside curved surfaces: the torus encloses 2.8 % less than the exact 2 pi^2 R r^2.
std::vector<MeshSpec> mesh_specs() {
  using V = Vec3d;
  return {
      {"meat_slab", meat_slab(), V(-0.42, -0.27, -0.09), V(0.42, 0.27, 0.09), 0.006, 0.3},
      {"orange_slice", orange_slice(), V(-0.02, -0.14, -0.37), V(0.37, 0.14, 0.37), 0.006, 0.2},
      {"orange_pulp", orange_pulp(), V(-0.06, -0.14, -0.33), V(0.33, 0.14, 0.33), 0.006, 0.2},
      {"fish", fish(), V(-0.46, -0.11, -0.16), V(0.34, 0.11, 0.21), 0.004, 0.3},
      {"heart", heart(), V(-0.37, -0.23, -0.32), V(0.37, 0.23, 0.39), 0.005, 0.2},
      {"femur", femur(), V(-0.18, -0.1, -0.42), V(0.12, 0.11, 0.44), 0.004, 0.2},
      {"armadillo", armadillo(), V(-0.34, -0.24, -0.42), V(0.23, 0.24, 0.47), 0.006, 0.4},
      {"tapered_tube", tapered_tube(), V(-0.22, -0.22, -0.32), V(0.22, 0.22, 0.32), 0.006, 0.3},
      {"torus", torus(), V(-0.42, -0.42, -0.12), V(0.42, 0.42, 0.12), 0.006, 0.15},
  };
}

struct Made {
  TriMesh mesh;
  std::unique_ptr<MeshSolid> solid;  // the mesh as a scene loads it
};

// The mesh with its coordinates rounded to multiples of kRound, vertices that came out equal
// merged (OpenVDB puts two vertices at one place at a cusp, and rounding can join two that are
// closer than kRound), and triangles left with a repeated corner dropped; then checked as a
// scene would load it: MeshSolid throws unless it is closed, 2-manifold, consistently oriented.
Made make_mesh(const MeshSpec& spec) {
  const TriMesh raw = mesh_implicit(spec.sdf, spec.lo, spec.hi, spec.voxel, spec.adaptivity);
  Made m;
  std::map<std::array<float, 3>, int32_t> index_of;
  std::vector<int32_t> index(raw.vertices.size());
  std::vector<Vec3d> v;
  for (size_t i = 0; i < raw.vertices.size(); ++i) {
    std::array<float, 3> p;
    for (int d = 0; d < 3; ++d)
      p[d] = float(std::round(double(raw.vertices[i][d]) / kRound) * kRound);
    const auto [it, fresh] = index_of.emplace(p, int32_t(m.mesh.vertices.size()));
    if (fresh) m.mesh.vertices.emplace_back(p[0], p[1], p[2]), v.emplace_back(p[0], p[1], p[2]);
    index[i] = it->second;
  }
  for (const auto& t : raw.triangles) {
    const std::array<int32_t, 3> r = {index[t[0]], index[t[1]], index[t[2]]};
    if (r[0] != r[1] && r[1] != r[2] && r[2] != r[0]) m.mesh.triangles.push_back(r);
  }
  m.solid = std::make_unique<MeshSolid>(v, m.mesh.triangles, spec.name);
  if (m.solid->turned_inside_out()) throw std::runtime_error(std::string(spec.name) + ": inward");
  return m;
}

int run(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: make_meshes OUT_DIR [--threads N] [NAME ...]\n");
    return 2;
  }
  const std::string out = argv[1];
  int threads = 0;
  std::vector<std::string> names;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--threads" && i + 1 < argc)
      threads = std::atoi(argv[++i]);
    else
      names.push_back(a);
  }
  std::vector<const MeshSpec*> wanted;
  const std::vector<MeshSpec> specs = mesh_specs();
  for (const MeshSpec& spec : specs) {
    bool named = names.empty();
    for (const std::string& n : names) named = named || n == spec.name;
    if (named) wanted.push_back(&spec);
  }
  if (wanted.size() != (names.empty() ? specs.size() : names.size())) {
    std::fprintf(stderr, "make_meshes: unknown or repeated mesh name among the arguments\n");
    return 2;
  }
  const ThreadLimit limit(threads);
  make_directories(out);
  std::printf("| mesh | bounding box (min .. max) | triangles | vertices | bytes | volume |\n");
  std::printf("|---|---|---:|---:|---:|---:|\n");
  for (const MeshSpec* spec : wanted) {
    const Made m = make_mesh(*spec);
    const std::string bytes = encode_obj(m.mesh);
    write_file_atomic(out + "/" + spec->name + ".obj", bytes);
    const Vec3d lo = m.solid->lo(), hi = m.solid->hi();
    std::printf(
        "| `%s.obj` | (%.3f, %.3f, %.3f) .. (%.3f, %.3f, %.3f) | %zu | %zu | %zu | %.5f |\n",
        spec->name, lo.x(), lo.y(), lo.z(), hi.x(), hi.y(), hi.z(), m.mesh.triangles.size(),
        m.mesh.vertices.size(), bytes.size(), m.solid->volume());
  }
  return 0;
}

}  // namespace
}  // namespace tear

int main(int argc, char** argv) {
  try {
    return tear::run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "make_meshes: %s\n", e.what());
    return 1;
  }
}
