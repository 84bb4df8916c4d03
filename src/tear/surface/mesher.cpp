// mesh_particles: particles -> narrow-band level set (OpenVDB) -> triangle mesh; mesh_implicit:
// a formula's signed distance -> the same mesher. The steps that need OpenVDB run in its module
// (level_set.h, openvdb/level_set.cpp), loaded the first time a mesh is made; this file decides
// what they get. Lengths below are in particle spacings s.
//
// 1. Undamaged particles become a union of spheres of radius r (ParticlesToLevelSet). r must
//    exceed half the lattice's body diagonal (sqrt(3)/2) for the union to have no holes; the
//    default, 1, leaves margin for stretched material.
// 2. Damaged particles (damage > threshold) carve spheres of radius kCarve out of it (CSG
//    difference). Dropping them alone does not open a crack one particle wide: spheres of
//    radius 1 from its two sides meet across the gap of 2. On a lattice the holes of one damaged
//    layer overlap into a sheet at least 2 sqrt(kCarve^2 - 1/2) ~ 1.4 thick, about three voxels,
//    which smoothing does not close, whatever the lattice's offset and rotation; kCarve = 0.85
//    was enough there but left bridges at the rim of stratified-random samples (tests/surface).
// 3. 2D frames (z equal everywhere): the particles are copied to z = -1/2, 0, 1/2 and the level
//    set is cut by the slab |z - z0| <= 1/2 + inset, so that the mesh is one spacing thick.
// 4. The level set is rebuilt as a clean signed distance, smoothed (mean-value filter,
//    renormalised by OpenVDB's tracker) and meshed `inset` = r - 0.65 inside (volumeToMesh at
//    that isovalue): a smoothed union of spheres bulges about that far past the half spacing
//    that each particle's volume reaches. Enclosed volumes come out within ~3% of the
//    particles' (a lattice-sampled ball +2..3%, a block -1%; tests/surface).
// 5. Quads are split along their shorter diagonal; OpenVDB orders the corners clockwise seen
//    from outside, so each triangle is reversed.
//
// The result does not depend on the thread count (tested at 1 and 2 threads).
#include "tear/surface/mesher.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

#include "tear/exec/parallel.h"
#include "tear/surface/level_set.h"

namespace tear {

namespace {

constexpr double kDefaultRadius = 1.0;  // sphere radius, spacings
constexpr double kDefaultVoxel = 0.5;   // voxel size, spacings
constexpr int kDefaultSmooth = 2;       // mean-value filter passes
constexpr double kCarve = 1.0;          // radius of a damaged particle's hole, spacings
constexpr double kBulge = 0.65;         // a smoothed union of radius r reaches r - kBulge too far
constexpr float kHalfWidth = 3;         // narrow band half width, voxels
constexpr double kMinRadius = 1.5;      // voxels: ParticlesToLevelSet skips smaller spheres

void check(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("mesh: " + what);
}

}  // namespace

void check_mesh_options(const MeshOptions& o) {
  check(std::isfinite(o.spacing) && o.spacing >= 0, "spacing must be >= 0 (0: estimated)");
  check(std::isfinite(o.radius) && o.radius >= 0, "radius must be >= 0 (0: default)");
  check(std::isfinite(o.voxel) && o.voxel >= 0, "voxel must be >= 0 (0: default)");
  check(o.smooth >= -1 && o.smooth <= 100, "smooth must be in [0, 100] (-1: default)");
  check(!std::isnan(o.damage_threshold), "damage threshold must be a number");
  const double radius = o.radius > 0 ? o.radius : kDefaultRadius;
  const double voxel = o.voxel > 0 ? o.voxel : kDefaultVoxel;
  std::ostringstream why;
  why << "voxel " << voxel << " is too coarse for radius " << radius
      << " (in spacings): the voxel must be at most the radius / 1.5";
  check(radius >= kMinRadius * voxel, why.str());
}

TriMesh mesh_particles(const PointTable& frame, const MeshOptions& o) {
  check_mesh_options(o);
  const double radius = o.radius > 0 ? o.radius : kDefaultRadius;
  const double voxel = o.voxel > 0 ? o.voxel : kDefaultVoxel;
  const int smooth = o.smooth >= 0 ? o.smooth : kDefaultSmooth;

  TriMesh mesh;
  if (frame.count == 0) return mesh;
  const double h = o.spacing > 0 ? o.spacing : estimate_spacing(frame);
  if (!(h > 0))
    throw std::runtime_error(
        "mesh: cannot estimate the particle spacing (fewer than two distinct points); give "
        "the spacing");

  const std::vector<Eigen::Vector3d> centre = positions(frame);
  const std::vector<double>* damage = frame.has("damage") ? &frame.column("damage") : nullptr;
  const double z0 = centre[0].z();
  const bool flat = std::all_of(centre.begin(), centre.end(),
                                [&](const Eigen::Vector3d& p) { return p.z() == z0; });
  SpheresSurface s;
  s.inset = std::max(0.0, radius - kBulge) * h;
  // A coarse voxel widens the holes, so that one damaged layer still parts the two sides.
  s.carve = std::max(kCarve, kMinRadius * voxel) * h;
  s.radius = radius * h;
  s.voxel = voxel * h;
  s.smooth = smooth;
  s.half_width = kHalfWidth;

  const std::vector<double> layers =
      flat ? std::vector<double>{-h / 2, 0, h / 2} : std::vector<double>{0};
  for (size_t i = 0; i < frame.count; ++i) {
    const Eigen::Vector3d& p = centre[i];
    if (!p.allFinite()) continue;
    std::vector<Eigen::Vector3d>& list =
        damage && (*damage)[i] > o.damage_threshold ? s.carved : s.whole;
    for (double dz : layers) list.emplace_back(p.x(), p.y(), p.z() + dz);
  }
  if (s.whole.empty()) return mesh;
  // Index coordinates must fit OpenVDB's 32-bit ones.
  for (const Eigen::Vector3d& p : s.whole)
    if (std::abs(p.x()) + std::abs(p.y()) + std::abs(p.z()) > 1e9 * voxel * h)
      throw std::runtime_error("mesh: spacing " + std::to_string(h) + " is too small for points " +
                               "as far as (" + std::to_string(p.x()) + ", " +
                               std::to_string(p.y()) + ", " + std::to_string(p.z()) + ")");
  if (flat) {
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::max()), hi = -lo;
    for (const Eigen::Vector3d& p : s.whole) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    const double pad = (radius + 2 * kHalfWidth * voxel) * h;
    const double half = 0.5 * h + s.inset;
    s.slab = true;
    s.slab_lo = Eigen::Vector3d(lo.x() - pad, lo.y() - pad, z0 - half);
    s.slab_hi = Eigen::Vector3d(hi.x() + pad, hi.y() + pad, z0 + half);
  }
  return level_set_module().spheres(s);
}

TriMesh mesh_implicit(const std::function<double(const Eigen::Vector3d&)>& sdf,
                      const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, double voxel,
                      double adaptivity) {
  if (!(voxel > 0) || !(adaptivity >= 0 && adaptivity <= 1) || !lo.allFinite() || !hi.allFinite() ||
      !(hi.array() > lo.array()).all())
    throw std::invalid_argument("mesh_implicit: needs voxel > 0, adaptivity in [0, 1], lo < hi");
  // Voxel centres at integer multiples of the voxel (OpenVDB's linear transform), over the box.
  SampledSurface s;
  s.voxel = voxel;
  s.adaptivity = adaptivity;
  s.band = float(kHalfWidth * voxel);
  const Eigen::Vector3i a(int(std::floor(lo.x() / voxel)), int(std::floor(lo.y() / voxel)),
                          int(std::floor(lo.z() / voxel)));
  const Eigen::Vector3i b(int(std::ceil(hi.x() / voxel)), int(std::ceil(hi.y() / voxel)),
                          int(std::ceil(hi.z() / voxel)));
  s.lo = a;
  s.n = b - a + Eigen::Vector3i::Ones();
  const size_t count = size_t(s.n.x()) * size_t(s.n.y()) * size_t(s.n.z());
  s.value.resize(count);
  parallel_for(count, [&](size_t i) {
    const Eigen::Vector3i c = s.voxel_of(i);
    s.value[i] = float(sdf(voxel * Eigen::Vector3d(c.x(), c.y(), c.z())));
  });
  for (size_t i = 0; i < count; ++i) {
    const Eigen::Vector3i c = s.voxel_of(i);
    const bool side = c.x() == a.x() || c.x() == b.x() || c.y() == a.y() || c.y() == b.y() ||
                      c.z() == a.z() || c.z() == b.z();
    if (side && !(s.value[i] > 0))
      throw std::invalid_argument("mesh_implicit: the solid reaches the side of the box at (" +
                                  std::to_string(voxel * c.x()) + ", " +
                                  std::to_string(voxel * c.y()) + ", " +
                                  std::to_string(voxel * c.z()) + ")");
  }
  return level_set_module().sampled(s);
}

const char* openvdb_version() { return level_set_module().openvdb_version(); }

}  // namespace tear
