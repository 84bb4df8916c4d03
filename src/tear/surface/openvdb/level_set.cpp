// The surface mesher's OpenVDB half, built as the module libtear_level_set.so (level_set.h):
// spheres and sampled signed distances to narrow-band level sets, CSG, rebuild, smoothing and
// iso-surfaces. Every use of OpenVDB in tear is in this file; mesher.cpp says why each step is
// there. The result does not depend on the thread count: rasterisation and CSG take minima,
// filters read a copy of the previous values, and the mesher numbers points and polygons in
// leaf order.
#include "tear/surface/level_set.h"

#include <openvdb/openvdb.h>
#include <openvdb/tools/Composite.h>
#include <openvdb/tools/LevelSetFilter.h>
#include <openvdb/tools/LevelSetRebuild.h>
#include <openvdb/tools/MeshToVolume.h>
#include <openvdb/tools/ParticlesToLevelSet.h>
#include <openvdb/tools/Prune.h>
#include <openvdb/tools/VolumeToMesh.h>

#include <mutex>

#include "tear/math/types.h"

namespace tear {

namespace {

void initialize() {
  static std::once_flag once;
  std::call_once(once, [] { openvdb::initialize(); });
}

// The positions as ParticlesToLevelSet reads them.
struct ParticleList {
  using PosType = openvdb::Vec3R;
  std::vector<openvdb::Vec3R> p;
  explicit ParticleList(const std::vector<Eigen::Vector3d>& x) {
    p.reserve(x.size());
    for (const Eigen::Vector3d& q : x) p.emplace_back(q.x(), q.y(), q.z());
  }
  size_t size() const { return p.size(); }
  void getPos(size_t n, openvdb::Vec3R& xyz) const { xyz = p[n]; }
};

openvdb::FloatGrid::Ptr spheres(const ParticleList& particles, double radius, float half_width,
                                const openvdb::math::Transform::Ptr& xform) {
  // The background (the band's half width in world units) sets how far each sphere reaches.
  openvdb::FloatGrid::Ptr grid =
      openvdb::createLevelSet<openvdb::FloatGrid>(xform->voxelSize()[0], half_width);
  grid->setTransform(xform);
  openvdb::tools::ParticlesToLevelSet<openvdb::FloatGrid> raster(*grid);
  raster.rasterizeSpheres(particles, radius);
  raster.finalize(/*prune=*/true);
  TEAR_ASSERT(!raster.ignoredParticles());  // radii are at least 1.5 voxels (mesher.cpp)
  return grid;
}

// The surface {grid = isovalue} (volumeToMesh; adaptivity in [0, 1] merges voxels where it is
// flat), as counter-clockwise triangles seen from outside: OpenVDB orders the corners
// clockwise seen from outside, so each triangle is reversed; quads are split along their
// shorter diagonal.
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

TriMesh spheres_surface(const SpheresSurface& s) {
  initialize();
  const openvdb::math::Transform::Ptr xform =
      openvdb::math::Transform::createLinearTransform(s.voxel);
  openvdb::FloatGrid::Ptr grid = spheres(ParticleList(s.whole), s.radius, s.half_width, xform);
  if (!s.carved.empty()) {
    openvdb::FloatGrid::Ptr holes = spheres(ParticleList(s.carved), s.carve, s.half_width, xform);
    openvdb::tools::csgDifference(*grid, *holes);
  }
  if (s.slab) {
    const openvdb::math::BBox<openvdb::Vec3d> box(
        openvdb::Vec3d(s.slab_lo.x(), s.slab_lo.y(), s.slab_lo.z()),
        openvdb::Vec3d(s.slab_hi.x(), s.slab_hi.y(), s.slab_hi.z()));
    openvdb::FloatGrid::Ptr cut =
        openvdb::tools::createLevelSetBox<openvdb::FloatGrid>(box, *xform, s.half_width);
    openvdb::tools::csgIntersection(*grid, *cut);
  }
  grid = openvdb::tools::levelSetRebuild(*grid, 0, s.half_width);
  if (s.smooth > 0) {
    openvdb::tools::LevelSetFilter<openvdb::FloatGrid> filter(*grid);
    for (int i = 0; i < s.smooth; ++i) filter.mean(1);
  }
  return iso_surface(*grid, -s.inset, 0.0);
}

TriMesh sampled_surface(const SampledSurface& s) {
  initialize();
  // The narrow band active; deeper inside, inactive voxels of the inside value (a closed
  // surface then needs no flood fill, whatever the values are far from it).
  openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(s.band);
  grid->setTransform(openvdb::math::Transform::createLinearTransform(s.voxel));
  grid->setGridClass(openvdb::GRID_LEVEL_SET);
  openvdb::FloatGrid::Accessor acc = grid->getAccessor();
  for (size_t i = 0; i < s.value.size(); ++i) {
    const Eigen::Vector3i at = s.voxel_of(i);
    const openvdb::Coord c(at.x(), at.y(), at.z());
    const float v = s.value[i];
    if (std::abs(v) < s.band)
      acc.setValue(c, v);
    else if (v < 0)
      acc.setValueOff(c, -s.band);
  }
  openvdb::tools::pruneLevelSet(grid->tree());
  return iso_surface(*grid, 0.0, s.adaptivity);
}

const char* openvdb_version() { return OPENVDB_LIBRARY_VERSION_STRING; }

}  // namespace

}  // namespace tear

extern "C" __attribute__((visibility("default"))) const tear::LevelSetModule*
tear_level_set_module() {
  static const tear::LevelSetModule module{tear::kLevelSetAbi, tear::spheres_surface,
                                           tear::sampled_surface, tear::openvdb_version};
  return &module;
}
