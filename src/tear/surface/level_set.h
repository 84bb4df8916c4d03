// surface/: what the mesher (mesher.cpp) hands its OpenVDB half and gets back. The OpenVDB half
// (openvdb/level_set.cpp) is a module, libtear_level_set.so, loaded the first time a mesh is
// made (level_set_module()): OpenVDB's shared library binds about 70 000 symbols when it is
// loaded, 50-70 ms at the start of every process that links it, which runs, checks and renders
// without surfaces do not need. Plain data crosses, no OpenVDB type.
#pragma once

#include "tear/io/mesh_io.h"

#include <Eigen/Core>
#include <vector>

namespace tear {

// A union of spheres minus holes, rebuilt as a signed distance, smoothed and meshed `inset`
// inside (mesh_particles). Lengths in world units.
struct SpheresSurface {
  std::vector<Eigen::Vector3d> whole;   // centres of the spheres of radius `radius`
  std::vector<Eigen::Vector3d> carved;  // centres of the holes of radius `carve`
  double radius = 0, carve = 0, voxel = 0, inset = 0;
  int smooth = 0;            // mean-value filter passes
  float half_width = 0;      // narrow band half width, voxels
  bool slab = false;         // cut by the box [slab_lo, slab_hi] (2D frames)
  Eigen::Vector3d slab_lo = Eigen::Vector3d::Zero(), slab_hi = Eigen::Vector3d::Zero();
};

// Signed distances sampled at voxel centres voxel * (lo + (i % n.x, i / n.x % n.y,
// i / n.x / n.y)) for i < n.x n.y n.z, meshed at 0 (mesh_implicit). Values within `band` of 0
// are the narrow band; negative ones beyond it are the inside.
struct SampledSurface {
  Eigen::Vector3i lo = Eigen::Vector3i::Zero(), n = Eigen::Vector3i::Zero();
  double voxel = 0, adaptivity = 0;
  float band = 0;
  std::vector<float> value;
  // The integer coordinates of value[i]'s voxel.
  Eigen::Vector3i voxel_of(size_t i) const {
    const size_t nx = size_t(n.x()), ny = size_t(n.y());
    return lo + Eigen::Vector3i(int(i % nx), int(i / nx % ny), int(i / nx / ny));
  }
};

// The module's functions; `abi` is the kLevelSetAbi it was built with.
struct LevelSetModule {
  int abi;
  TriMesh (*spheres)(const SpheresSurface&);
  TriMesh (*sampled)(const SampledSurface&);
  const char* (*openvdb_version)();
};

// Changed with the structs above, so that a module of another build is refused.
constexpr int kLevelSetAbi = 1;
// The module's entry point: extern "C" const LevelSetModule* tear_level_set_module().
#define TEAR_LEVEL_SET_ENTRY "tear_level_set_module"
#define TEAR_LEVEL_SET_FILE "libtear_level_set.so"

// The module, loaded once (thread-safe) from $TEAR_MODULE_DIR where that is set, else from the
// running program's folder or, failing that, the build folder tear was built in (for the
// tests). Throws std::runtime_error naming each file tried and why it failed.
const LevelSetModule& level_set_module();

}  // namespace tear
