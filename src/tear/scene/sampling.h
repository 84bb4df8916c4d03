// scene/: turning object descriptions into particles (positions, fiber frames, velocities).
#pragma once

#include "tear/particles/particles.h"
#include "tear/scene/scene.h"

#include <vector>

namespace tear {

// Sample every object of the scene into particles, deterministically from scene.seed:
// stratified random (or regular lattice for "sampling": "grid") at `ppc` per cell of size dx,
// mass = rho dx^dim / ppc, vol0 = dx^dim / ppc, initial velocity v + omega x (x - centre),
// fiber frame from the object's fiber field. Ids are 0..n-1 in sampling order.
template <int Dim>
Particles<Dim> sample_scene(const Scene& scene);

// Every group of the scene: the solids' particles (sample_scene, group 0, empty where the scene
// has no solid), then for curves and for surfaces, where the scene has some, a group of mesh
// vertices followed by its group of element particles (codim/elements.h append_codim_body),
// objects in scene order within each.
template <int Dim>
std::vector<Particles<Dim>> sample_scene_groups(const Scene& scene);

// Orthonormal fiber frame [a1 a2 (a1 x a2)] of the object's fiber field at world point p.
template <int Dim>
Mat<Dim> fiber_frame_at(const FiberSpec& f, const Vec3d& p, uint64_t random_key);

}  // namespace tear
