// surface/: particles to a closed triangle surface (OpenVDB narrow-band level set, then
// iso-surface), with cracks left open: particles damaged past a threshold do not join the
// two sides of a crack. What `tear mesh` and the renderer's surface mode use; also implicit
// solids to meshes (the shipped meshes of examples/meshes/). Knows io/'s point tables and
// meshes, nothing of scenes or the simulation; OpenVDB stays inside its module (level_set.h).
#pragma once

#include "tear/io/mesh_io.h"
#include "tear/io/point_table.h"

#include <Eigen/Core>
#include <functional>

namespace tear {

struct MeshOptions {
  double spacing = 0;             // particle spacing; 0: estimate_spacing(frame)
  double radius = 0;              // sphere radius per particle, in spacings; 0: default 1
  double voxel = 0;               // voxel size, in spacings; 0: default 0.5
  int smooth = -1;                // mean-filter passes over the level set; -1: default 2
  double damage_threshold = 0.5;  // particles with damage above it open the surface
};

// The surface of the particles of one frame (columns x y z, and damage when present; no z
// column reads as z = 0): closed, manifold, counter-clockwise seen from outside, enclosing
// about the particles' volume (spacing^3 each). Particles with damage > damage_threshold carve
// a hole of one spacing, so that one damaged layer splits a body in two. 2D frames (z equal
// everywhere) are meshed as a slab one spacing thick. Points with a non-finite coordinate are
// left out. Resolution: fragments of a few particles come out smaller (3 x 3 x 3 particles keep
// about 2/3 of their volume) and a lone particle vanishes; a finer voxel keeps them. The same bytes
// for any thread count. Throws std::invalid_argument on bad options and std::runtime_error when the
// spacing cannot be estimated (fewer than two distinct points).
TriMesh mesh_particles(const PointTable& frame, const MeshOptions& options);

// The surface {sdf = 0} of an implicit solid (sdf < 0 inside), for meshes made from formulas
// (tools/make_meshes.cpp): sdf is sampled at voxel centres over the box [lo, hi] (in parallel:
// it must be safe to call from several threads), which must hold the solid with at least one
// voxel to spare (std::invalid_argument otherwise), and meshed by OpenVDB's volumeToMesh;
// `adaptivity` in [0, 1] merges voxels where the surface is flat (0: one or two triangles a
// voxel). sdf must have the right sign everywhere; its values matter only within 3 voxels of
// the surface, where an estimate of the distance serves (a smooth union, a scaled implicit
// function). Closed, counter-clockwise seen from outside; the same bytes for any thread count.
TriMesh mesh_implicit(const std::function<double(const Eigen::Vector3d&)>& sdf,
                      const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, double voxel,
                      double adaptivity);

// Throws std::invalid_argument naming the option when mesh_particles would reject `options`.
void check_mesh_options(const MeshOptions& options);

// The OpenVDB version the mesher's module was compiled against (`tear info`). The module
// (level_set.h) is loaded the first time this, mesh_particles or mesh_implicit is called;
// each throws std::runtime_error saying where it looked when it cannot be loaded.
const char* openvdb_version();

// Median distance from a point to its nearest neighbour (coincident points left out): the
// particle spacing of a frame. 0 when there are fewer than two distinct finite points.
double estimate_spacing(const PointTable& frame);

}  // namespace tear
