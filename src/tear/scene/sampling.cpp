// Sampling objects into particles and evaluating fiber fields (SCENE_FORMAT.md "objects").
// Randomness comes from a counter-based hash of (seed, object, cell) so the result does not
// depend on iteration order, thread count or the standard library.
#include "tear/scene/sampling.h"

#include "tear/codim/elements.h"

#include "tear/exec/parallel.h"

#include "tear/geometry/shape.h"
#include "tear/scene/flow_fibers.h"
#include "tear/scene/scene_parts.h"

#include <algorithm>
#include <cmath>
#include <memory>

namespace tear {

namespace {

constexpr double kPi = 3.14159265358979323846;

uint64_t splitmix64(uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

uint64_t hash_combine(uint64_t h, uint64_t v) { return splitmix64(h ^ splitmix64(v)); }

// splitmix64 stream; uniform() is in [0, 1) with 53 random bits.
struct Rng {
  uint64_t state;
  explicit Rng(uint64_t key) : state(key) {}
  uint64_t next() {
    state += 0x9E3779B97F4A7C15ull;
    uint64_t z = state;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double uniform() { return double(next() >> 11) * 0x1.0p-53; }
};

// Any unit vector orthogonal to unit a (3D): Gram-Schmidt of the least aligned coordinate axis.
Vec3d any_orthogonal(const Vec3d& a) {
  int i = 0;
  a.cwiseAbs().minCoeff(&i);
  Vec3d e = Vec3d::Unit(i);
  return (e - e.dot(a) * a).normalized();
}

// Unit radial direction of p from the fiber centre (3D: perpendicular to the axis);
// false at the centre/axis where it is undefined.
bool radial_dir(const FiberSpec& f, const Vec3d& p, int dim, Vec3d* out) {
  Vec3d d = p - f.center;
  if (dim == 2) {
    d.z() = 0;
  } else {
    d -= d.dot(f.axis) * f.axis;
  }
  double n = d.norm();
  if (!(n > 1e-12)) return false;
  *out = d / n;
  return true;
}

// Reads a uniform random unit vector in Dim dimensions from the key.
Vec3d random_unit(uint64_t key, int dim) {
  Rng rng(hash_combine(key, 0xF1B3E5ull));
  double u = rng.uniform(), v = rng.uniform();
  double phi = 2 * kPi * u;
  if (dim == 2) return Vec3d(std::cos(phi), std::sin(phi), 0);
  double z = 2 * v - 1, s = std::sqrt(std::max(0.0, 1 - z * z));
  return Vec3d(s * std::cos(phi), s * std::sin(phi), z);
}

}  // namespace

template <int Dim>
Mat<Dim> fiber_frame_at(const FiberSpec& f, const Vec3d& p, uint64_t random_key) {
  Vec3d a1 = Vec3d::UnitX(), radial;
  Vec3d axis = f.axis.norm() > 0 ? Vec3d(f.axis.normalized()) : Vec3d::UnitZ();
  if (Dim == 2) axis.z() = 0;
  bool has_radial = radial_dir(f, p, Dim, &radial);
  // Natural second direction when a2 is not given (3D): the axis for radial and
  // circumferential fields, the radial direction for longitudinal ones.
  Vec3d a2_hint = Vec3d::Zero();
  switch (f.type) {
    case FiberField::Constant: a1 = f.a1; break;
    case FiberField::Radial:
      a1 = has_radial ? radial : any_orthogonal(Dim == 3 ? axis : Vec3d::UnitZ());
      a2_hint = axis;
      break;
    case FiberField::Circumferential:
      if (!has_radial) radial = any_orthogonal(Dim == 3 ? axis : Vec3d::UnitZ());
      a1 = Dim == 3 ? Vec3d(axis.cross(radial)) : Vec3d(-radial.y(), radial.x(), 0);
      a2_hint = axis;
      break;
    case FiberField::Longitudinal:
      a1 = axis;
      if (has_radial) a2_hint = radial;
      break;
    case FiberField::Random: a1 = random_unit(random_key, Dim); break;
    // Not fields of position: the sampler frames each particle's flow direction or file
    // fibers as a constant field (sample_scene).
    case FiberField::Flow:
    case FiberField::FromFile: a1 = f.a1; break;
  }
  if (Dim == 2) a1.z() = 0;
  if (!(a1.norm() > 0)) a1 = Vec3d::UnitX();
  a1.normalize();
  if (f.spread > 0) {
    Rng rng(hash_combine(random_key, 0x5B7EADull));
    const double u = rng.uniform(), v = rng.uniform(), max = f.spread * kPi / 180;
    if (Dim == 2) {
      const double t = (2 * u - 1) * max, c = std::cos(t), s = std::sin(t);
      a1 = Vec3d(c * a1.x() - s * a1.y(), s * a1.x() + c * a1.y(), 0);
    } else {
      const Vec3d e1 = any_orthogonal(a1), e2 = a1.cross(e1);
      const double phi = 2 * kPi * v, t = u * max;
      a1 = std::cos(t) * a1 + std::sin(t) * (std::cos(phi) * e1 + std::sin(phi) * e2);
    }
    a1.normalize();
  }

  Mat<Dim> D;
  if constexpr (Dim == 2) {
    // In 2D the proper frame is [a1, perp(a1)]; a given a2 only fixes a line, not a sign.
    D << Real(a1.x()), Real(-a1.y()), Real(a1.y()), Real(a1.x());
  } else {
    Vec3d a2 = f.has_a2 ? f.a2 : a2_hint;
    a2 -= a2.dot(a1) * a1;
    if (a2.norm() < 1e-9) {
      a2 = any_orthogonal(a1);
    } else {
      a2.normalize();
    }
    D.col(0) = a1.cast<Real>();
    D.col(1) = a2.cast<Real>();
    D.col(2) = a1.cross(a2).cast<Real>();
  }
  return D;
}

namespace {

// The sampling cells of object `obj`: the inclusive cell range [c0, c1] overlapping its
// shape's bounds and the domain; false where that is empty. Cells in order, x fastest, give
// the particle ids.
template <int Dim>
bool cell_range(const Scene& scene, size_t obj, IVec<Dim>* c0, IVec<Dim>* c1) {
  const double dx = scene.dx;
  Vec3d lo, hi;
  scene.objects[obj].shape.bounds(&lo, &hi);
  bool empty = false;
  for (int d = 0; d < Dim; ++d) {
    const int ncell =
        std::max(1, int(std::ceil((scene.domain_max[d] - scene.domain_min[d]) / dx - 1e-9)));
    double a = std::floor((lo[d] - scene.domain_min[d]) / dx);
    double b = std::ceil((hi[d] - scene.domain_min[d]) / dx) - 1;
    // Clamped in double first: a shape far outside the domain must not overflow the int.
    (*c0)[d] = int(std::clamp(a, 0.0, double(ncell)));
    (*c1)[d] = int(std::clamp(b, -1.0, double(ncell - 1)));
    empty = empty || (*c0)[d] > (*c1)[d];
  }
  return !empty;
}

// fn(p, key, s) for the sample points of one cell of an object that lie inside its shape and
// the domain, in order. `key` seeds the cell's random numbers (with s, the fiber field's).
template <int Dim, class Fn>
void cell_samples(const Scene& scene, size_t obj, const IVec<Dim>& c, Fn&& fn) {
  const double dx = scene.dx;
  const ObjectSpec& o = scene.objects[obj];
  const int k = scene_detail::ppc_root(o.ppc, Dim);  // 0: not a perfect power
  uint64_t key = hash_combine(hash_combine(0x7EA5ull, scene.seed), obj);
  for (int d = 0; d < Dim; ++d) key = hash_combine(key, uint64_t(uint32_t(c[d])));
  Rng rng(key);
  Vec3d origin = Vec3d::Zero();
  for (int d = 0; d < Dim; ++d) origin[d] = scene.domain_min[d] + c[d] * dx;
  for (int s = 0; s < o.ppc; ++s) {
    Vec3d p = origin;
    if (k > 0) {  // stratified: one jittered (or centred) point per sub-cell
      int rem = s;
      for (int d = 0; d < Dim; ++d) {
        int sub = rem % k;
        rem /= k;
        double u = o.grid_sampling ? 0.5 : rng.uniform();
        p[d] += (sub + u) * dx / k;
      }
    } else {
      for (int d = 0; d < Dim; ++d) p[d] += rng.uniform() * dx;
    }
    bool in_domain = true;
    for (int d = 0; d < Dim; ++d)
      in_domain = in_domain && p[d] >= scene.domain_min[d] && p[d] <= scene.domain_max[d];
    if (!in_domain || !o.shape.inside(p)) continue;
    fn(p, key, s);
  }
}

}  // namespace

template <int Dim>
Particles<Dim> sample_scene(const Scene& scene) {
  // Two passes over the same points: count each cell's, then fill the store, sized once, cell
  // by cell in parallel at the cells' offsets (each cell's random numbers come from its own
  // key, so the particles and their ids do not depend on the thread count).
  struct Cell {
    size_t object;
    IVec<Dim> c;
    size_t first;  // index of the cell's first particle
  };
  // Objects in order; a "particles" object is one cell of all its points, in file order.
  // A sampled object's cells that hold points are found row by row (the cells along x) in
  // parallel, and kept in row order.
  std::vector<Cell> cells;
  size_t n = 0;
  for (size_t obj = 0; obj < scene.objects.size(); ++obj) {
    if (scene.objects[obj].kind != ObjectKind::Volume) continue;  // sample_scene_groups
    if (const auto& pts = scene.objects[obj].points) {
      cells.push_back({obj, IVec<Dim>::Zero(), n});
      n += pts->x.size();
      continue;
    }
    IVec<Dim> c0, c1;
    if (!cell_range<Dim>(scene, obj, &c0, &c1)) continue;
    size_t rows = 1;
    for (int d = 1; d < Dim; ++d) rows *= size_t(c1[d] - c0[d] + 1);
    std::vector<std::vector<std::pair<IVec<Dim>, size_t>>> found(rows);
    parallel_for(rows, [&](size_t r) {
      IVec<Dim> c = c0;
      for (int d = 1, rest = int(r); d < Dim; ++d) {
        const int span = c1[d] - c0[d] + 1;
        c[d] = c0[d] + rest % span, rest /= span;
      }
      for (c[0] = c0[0]; c[0] <= c1[0]; ++c[0]) {
        size_t count = 0;
        cell_samples<Dim>(scene, obj, c, [&](const Vec3d&, uint64_t, int) { ++count; });
        if (count) found[r].push_back({c, count});
      }
    });
    for (const auto& row : found)
      for (const auto& [c, count] : row) cells.push_back({obj, c, n}), n += count;
  }
  // Flow fibers: each such object's potential flow, solved once before the particles.
  std::vector<std::unique_ptr<FlowField>> flows(scene.objects.size());
  for (size_t k = 0; k < scene.objects.size(); ++k) {
    const FiberSpec& f = scene.objects[k].fibers;
    if (f.type != FiberField::Flow) continue;
    try {
      flows[k] = std::make_unique<FlowField>(scene.objects[k].shape, Dim, scene.dx, f.sources,
                                             f.sinks,
                                             f.flow_radius > 0 ? f.flow_radius : 2 * scene.dx);
    } catch (const std::exception& e) {
      throw std::runtime_error(scene.file + ": objects[" + std::to_string(k) +
                               "].fibers: " + e.what());
    }
  }
  Particles<Dim> out;
  out.resize(n);
  const double cell_vol = std::pow(scene.dx, Dim);
  parallel_for(cells.size(), [&](size_t k) {
    const Cell& cell = cells[k];
    const ObjectSpec& o = scene.objects[cell.object];
    const Vec3d center = o.shape.world_center(), w = o.angular_velocity;
    size_t i = cell.first;
    // One particle at p (the file's point `point`, or -1 for a sampled one).
    auto add = [&](const Vec3d& p, uint64_t key, int s, long point) {
      const PointSet* pts = point >= 0 ? o.points.get() : nullptr;
      const Vec3d r = p - center;
      Vec3d vel =
          o.velocity + (Dim == 2 ? Vec3d(-w.z() * r.y(), w.z() * r.x(), 0) : Vec3d(w.cross(r)));
      if (pts && !pts->v.empty()) vel = pts->v[size_t(point)];
      out.id[i] = uint32_t(i);
      out.x[i] = p.head<Dim>().template cast<Real>();
      out.v[i] = vel.head<Dim>().template cast<Real>();
      // The file's material, else the first region that holds p, else the object's.
      int material = o.material;
      const FiberSpec* fibers = &o.fibers;
      for (const RegionSpec& region : o.regions)
        if (region.shape.inside(p)) {
          material = region.material, fibers = &region.fibers;
          break;
        }
      if (pts && !pts->material.empty()) material = pts->material[size_t(point)];
      FiberSpec own;  // flow, from_file: the point's own fibers, framed as a constant field
      own.spread = fibers->spread;
      if (fibers->type == FiberField::Flow) {
        own.a1 = flows[cell.object]->direction(p, fibers->a1);
        own.has_a2 = fibers->has_a2, own.a2 = fibers->a2;
        fibers = &own;
      } else if (fibers->type == FiberField::FromFile) {
        own.a1 = pts->a1[size_t(point)].normalized();
        own.has_a2 = !pts->a2.empty();
        if (own.has_a2) own.a2 = pts->a2[size_t(point)];
        fibers = &own;
      }
      out.fiber[i] = fiber_frame_at<Dim>(*fibers, p, hash_combine(key, uint64_t(s)));
      const double volume =
          pts && !pts->volume.empty() ? pts->volume[size_t(point)] : cell_vol / o.ppc;
      out.mass[i] = Real(scene.materials[size_t(material)].params.rho * volume);
      out.vol0[i] = Real(volume);
      out.material[i] = uint16_t(material);
      ++i;
    };
    if (o.points) {
      const uint64_t key = hash_combine(hash_combine(0x7EA5ull, scene.seed), cell.object);
      for (size_t k2 = 0; k2 < o.points->x.size(); ++k2)
        add(o.points->x[k2], key, int(k2), long(k2));
      return;
    }
    cell_samples<Dim>(scene, cell.object, cell.c,
                      [&](const Vec3d& p, uint64_t key, int s) { add(p, key, s, -1); });
  });
  out.drop_identity_fibers();
  return out;
}

template <int Dim>
std::vector<Particles<Dim>> sample_scene_groups(const Scene& scene) {
  std::vector<Particles<Dim>> groups;
  groups.push_back(sample_scene<Dim>(scene));
  for (ObjectKind kind : {ObjectKind::Curves, ObjectKind::Surface}) {
    Particles<Dim> vertices(GroupKind::MeshVertices);
    Particles<Dim> elements(kind == ObjectKind::Curves ? GroupKind::CurveElements
                                                       : GroupKind::SurfaceElements);
    for (const ObjectSpec& o : scene.objects) {
      if (o.kind != kind) continue;
      CodimBody body;
      body.material = uint16_t(o.material);
      body.rho = scene.materials[size_t(o.material)].params.rho;
      body.thickness = o.thickness;
      body.radius = o.radius;
      body.velocity = o.velocity;
      body.angular_velocity = o.angular_velocity;
      body.center = o.shape.world_center();
      if (kind == ObjectKind::Surface) body.warp = o.fibers.a1;
      append_codim_body<Dim>(*o.mesh, body, &vertices, &elements);
    }
    if (elements.size() == 0) continue;
    elements.vertex_group = int(groups.size());
    groups.push_back(std::move(vertices));
    groups.push_back(std::move(elements));
  }
  return groups;
}

template Particles<2> sample_scene<2>(const Scene&);
template std::vector<Particles<2>> sample_scene_groups<2>(const Scene&);
template std::vector<Particles<3>> sample_scene_groups<3>(const Scene&);
template Particles<3> sample_scene<3>(const Scene&);
template Mat<2> fiber_frame_at<2>(const FiberSpec&, const Vec3d&, uint64_t);
template Mat<3> fiber_frame_at<3>(const FiberSpec&, const Vec3d&, uint64_t);

}  // namespace tear
