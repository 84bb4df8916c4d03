// mesh_particles: particles -> narrow-band level set (OpenVDB) -> triangle mesh; mesh_implicit:
// a formula's signed distance -> the same mesher. Every use of OpenVDB in tear is in this file.
// Lengths below are in particle spacings s.
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
// The result does not depend on the thread count: rasterisation and CSG take minima, filters
// read a copy of the previous values, and the mesher numbers points and polygons in leaf order
// (tested at 1 and 2 threads).
#include "tear/surface/mesher.h"

#include <openvdb/openvdb.h>
#include <openvdb/tools/Composite.h>
#include <openvdb/tools/LevelSetFilter.h>
#include <openvdb/tools/LevelSetRebuild.h>
#include <openvdb/tools/MeshToVolume.h>
#include <openvdb/tools/ParticlesToLevelSet.h>
#include <openvdb/tools/Prune.h>
#include <openvdb/tools/VolumeToMesh.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <string>

#include "tear/exec/parallel.h"
#include "tear/math/types.h"

namespace tear {

namespace {

constexpr double kDefaultRadius = 1.0;  // sphere radius, spacings
constexpr double kDefaultVoxel = 0.5;   // voxel size, spacings
constexpr int kDefaultSmooth = 2;       // mean-value filter passes
constexpr double kCarve = 1.0;          // radius of a damaged particle's hole, spacings
constexpr double kBulge = 0.65;         // a smoothed union of radius r reaches r - kBulge too far
constexpr float kHalfWidth = 3;         // narrow band half width, voxels
constexpr double kMinRadius = 1.5;      // voxels: ParticlesToLevelSet skips smaller spheres

// The positions as ParticlesToLevelSet reads them.
struct ParticleList {
  using PosType = openvdb::Vec3R;
  std::vector<openvdb::Vec3R> p;
  size_t size() const { return p.size(); }
  void getPos(size_t n, openvdb::Vec3R& xyz) const { xyz = p[n]; }
};

openvdb::FloatGrid::Ptr spheres(const ParticleList& particles, double radius,
                                const openvdb::math::Transform::Ptr& xform) {
  // The background (the band's half width in world units) sets how far each sphere reaches.
  openvdb::FloatGrid::Ptr grid =
      openvdb::createLevelSet<openvdb::FloatGrid>(xform->voxelSize()[0], kHalfWidth);
  grid->setTransform(xform);
  openvdb::tools::ParticlesToLevelSet<openvdb::FloatGrid> raster(*grid);
  raster.rasterizeSpheres(particles, radius);
  raster.finalize(/*prune=*/true);
  TEAR_ASSERT(!raster.ignoredParticles());  // radii are at least kMinRadius voxels
  return grid;
}

// The surface {grid = isovalue} (volumeToMesh; adaptivity in [0, 1] merges voxels where it is
// flat), as counter-clockwise triangles seen from outside.
TriMesh iso_surface(const openvdb::FloatGrid& grid, double isovalue, double adaptivity) {
  std::vector<openvdb::Vec3s> points;
  std::vector<openvdb::Vec3I> triangles;
  std::vector<openvdb::Vec4I> quads;
  openvdb::tools::volumeToMesh(grid, points, triangles, quads, isovalue, adaptivity, true);

  TriMesh mesh;
  mesh.vertices.reserve(points.size());
  for (const openvdb::Vec3s& p : points) mesh.vertices.emplace_back(p.x(), p.y(), p.z());
  mesh.triangles.reserve(triangles.size() + 2 * quads.size());
  auto add = [&](uint32_t a, uint32_t b, uint32_t c) {
    mesh.triangles.push_back({int32_t(a), int32_t(c), int32_t(b)});  // reversed: CCW outside
  };
  for (const openvdb::Vec3I& t : triangles) add(t[0], t[1], t[2]);
  for (const openvdb::Vec4I& q : quads) {
    const auto& v = mesh.vertices;
    if ((v[q[0]] - v[q[2]]).squaredNorm() <= (v[q[1]] - v[q[3]]).squaredNorm())
      add(q[0], q[1], q[2]), add(q[0], q[2], q[3]);
    else
      add(q[0], q[1], q[3]), add(q[1], q[2], q[3]);
  }
  return mesh;
}

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
  const double inset = std::max(0.0, radius - kBulge) * h;
  // A coarse voxel widens the holes, so that one damaged layer still parts the two sides.
  const double carve = std::max(kCarve, kMinRadius * voxel) * h;

  ParticleList whole, carved;
  const std::vector<double> layers =
      flat ? std::vector<double>{-h / 2, 0, h / 2} : std::vector<double>{0};
  for (size_t i = 0; i < frame.count; ++i) {
    const Eigen::Vector3d& p = centre[i];
    if (!p.allFinite()) continue;
    ParticleList& list = damage && (*damage)[i] > o.damage_threshold ? carved : whole;
    for (double dz : layers) list.p.emplace_back(p.x(), p.y(), p.z() + dz);
  }
  if (whole.p.empty()) return mesh;
  // Index coordinates must fit OpenVDB's 32-bit ones.
  for (const openvdb::Vec3R& p : whole.p)
    if (std::abs(p.x()) + std::abs(p.y()) + std::abs(p.z()) > 1e9 * voxel * h)
      throw std::runtime_error("mesh: spacing " + std::to_string(h) + " is too small for points " +
                               "as far as (" + std::to_string(p.x()) + ", " +
                               std::to_string(p.y()) + ", " + std::to_string(p.z()) + ")");

  static std::once_flag init;
  std::call_once(init, [] { openvdb::initialize(); });
  const openvdb::math::Transform::Ptr xform =
      openvdb::math::Transform::createLinearTransform(voxel * h);
  openvdb::FloatGrid::Ptr grid = spheres(whole, radius * h, xform);
  if (!carved.p.empty()) {
    openvdb::FloatGrid::Ptr holes = spheres(carved, carve, xform);
    openvdb::tools::csgDifference(*grid, *holes);
  }
  if (flat) {
    openvdb::Vec3d lo(std::numeric_limits<double>::max()), hi(-lo);
    for (const openvdb::Vec3R& p : whole.p) lo = minComponent(lo, p), hi = maxComponent(hi, p);
    const double pad = (radius + 2 * kHalfWidth * voxel) * h;
    const double half = 0.5 * h + inset;
    const openvdb::math::BBox<openvdb::Vec3d> slab(
        openvdb::Vec3d(lo.x() - pad, lo.y() - pad, z0 - half),
        openvdb::Vec3d(hi.x() + pad, hi.y() + pad, z0 + half));
    openvdb::FloatGrid::Ptr box =
        openvdb::tools::createLevelSetBox<openvdb::FloatGrid>(slab, *xform, kHalfWidth);
    openvdb::tools::csgIntersection(*grid, *box);
  }
  grid = openvdb::tools::levelSetRebuild(*grid, 0, kHalfWidth);
  if (smooth > 0) {
    openvdb::tools::LevelSetFilter<openvdb::FloatGrid> filter(*grid);
    for (int i = 0; i < smooth; ++i) filter.mean(1);
  }

  return iso_surface(*grid, -inset, 0.0);
}

TriMesh mesh_implicit(const std::function<double(const Eigen::Vector3d&)>& sdf,
                      const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, double voxel,
                      double adaptivity) {
  if (!(voxel > 0) || !(adaptivity >= 0 && adaptivity <= 1) || !lo.allFinite() || !hi.allFinite() ||
      !(hi.array() > lo.array()).all())
    throw std::invalid_argument("mesh_implicit: needs voxel > 0, adaptivity in [0, 1], lo < hi");
  static std::once_flag init;
  std::call_once(init, [] { openvdb::initialize(); });
  // Voxel centres at integer multiples of the voxel (OpenVDB's linear transform), over the box.
  const openvdb::Coord a(int(std::floor(lo.x() / voxel)), int(std::floor(lo.y() / voxel)),
                         int(std::floor(lo.z() / voxel)));
  const openvdb::Coord b(int(std::ceil(hi.x() / voxel)), int(std::ceil(hi.y() / voxel)),
                         int(std::ceil(hi.z() / voxel)));
  const openvdb::Coord n = b - a + openvdb::Coord(1);
  const size_t count = size_t(n.x()) * size_t(n.y()) * size_t(n.z());
  auto coord = [&](size_t i) {
    return a + openvdb::Coord(int(i % size_t(n.x())), int(i / size_t(n.x()) % size_t(n.y())),
                              int(i / size_t(n.x()) / size_t(n.y())));
  };
  std::vector<float> value(count);
  parallel_for(count, [&](size_t i) {
    const openvdb::Coord c = coord(i);
    value[i] = float(sdf(voxel * Eigen::Vector3d(c.x(), c.y(), c.z())));
  });
  // The narrow band active; deeper inside, inactive voxels of the inside value (a closed
  // surface then needs no flood fill, whatever the estimate does far from it).
  const float band = float(kHalfWidth * voxel);
  openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(band);
  grid->setTransform(openvdb::math::Transform::createLinearTransform(voxel));
  grid->setGridClass(openvdb::GRID_LEVEL_SET);
  openvdb::FloatGrid::Accessor acc = grid->getAccessor();
  for (size_t i = 0; i < count; ++i) {
    const openvdb::Coord c = coord(i);
    const bool side = c.x() == a.x() || c.x() == b.x() || c.y() == a.y() || c.y() == b.y() ||
                      c.z() == a.z() || c.z() == b.z();
    if (side && !(value[i] > 0))
      throw std::invalid_argument("mesh_implicit: the solid reaches the side of the box at (" +
                                  std::to_string(voxel * c.x()) + ", " +
                                  std::to_string(voxel * c.y()) + ", " +
                                  std::to_string(voxel * c.z()) + ")");
    if (std::abs(value[i]) < band)
      acc.setValue(c, value[i]);
    else if (value[i] < 0)
      acc.setValueOff(c, -band);
  }
  openvdb::tools::pruneLevelSet(grid->tree());
  return iso_surface(*grid, 0.0, adaptivity);
}

const char* openvdb_version() { return OPENVDB_LIBRARY_VERSION_STRING; }

}  // namespace tear
