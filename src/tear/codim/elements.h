// codim/: codimensional bodies in MPM (Jiang et al. 2017): a curve or surface mesh made into
// particle groups of mesh vertices and element quadrature particles (particles/particles.h
// GroupKind), the in-manifold forces of the elements on their vertices, and the elements' state
// after G2P. Free functions over particle groups; the step (mpm/) calls them. Knows nothing of
// grids' transfers, scenes or files.
#pragma once

#include "tear/geometry/codim_mesh.h"
#include "tear/materials/material.h"
#include "tear/particles/particles.h"

#include <vector>

namespace tear {

// What the core needs of one codimensional body besides its mesh.
struct CodimBody {
  uint16_t material = 0;
  Real rho = 1;
  // The element volume: a triangle's area times `thickness`; a segment's length times its
  // cross-section, pi radius^2 in 3D, 2 radius in 2D (a slice of unit depth, as the 2D solids).
  double thickness = 0, radius = 0;
  // Initial motion v + omega x (x - center) (2D: omega along z).
  Vec3d velocity = Vec3d::Zero(), angular_velocity = Vec3d::Zero(), center = Vec3d::Zero();
  // Surfaces: the warp direction, projected onto each triangle as the first axis of its rest
  // frame (the model's kx acts along it, ky across); zero: the triangle's first edge.
  Vec3d warp = Vec3d::Zero();
};

// Appends the mesh's vertices to `vertices` (GroupKind::MeshVertices) and one quadrature
// particle per element, at its centroid, to `elements` (CurveElements or SurfaceElements, with
// vertex_group set by the caller). Mass and volume (supplement; ziran's MpmInitializationHelper
// gives each of an element's n_q quadrature particles and its gamma + 1 vertices an equal share
// of the element's volume, so that the elastic energy integrates only part of the element):
// here each element particle holds the element's whole volume V_e (its F is constant over a
// linear element, so one point integrates the elastic energy exactly) and no mass; each vertex
// holds the lumped mass rho V_e / (gamma + 1) of every element around it and no volume. All the
// momentum is on the vertices, which APIC transfers conserve exactly (element particles take
// their velocity from their vertices, not from the grid). The rest element lies on the axes
// (supplement §6): a segment's D = diag(L, 1, 1), a triangle's D = [[Dm, 0], [0, 1]] with Dm its
// edges in its rest frame, so the initial F is a rotation (the frame [t1 t2 n]).
template <int Dim>
void append_codim_body(const CodimMesh& mesh, const CodimBody& body, Particles<Dim>* vertices,
                       Particles<Dim>* elements);

// The elements' forces on the grid, through their vertices (supplement eqs. 6-15): with VP the
// element's volume times its first Piola stress (kept in the element group's `stress`),
//  - the in-manifold force (eqs. 12-13) on tangent corner b = 1..gamma is column b of
//    -VP_t Dm^-T (VP_t the tangent columns), and corner 0 takes minus their sum: `force`;
//  - the normal columns' stress tau_n = VP_n F_n^T (eq. 15: the term a solid's V P F^T is) is
//    shared equally by the element's corners, each spreading its share through its own weight
//    gradients as an MLS affine term: the vertices' `stress`, summed.
// The supplement spreads tau_n through the element particle's own weight gradients. With no
// mass at the element particle, a grid node reached by it but barely by a vertex then gets a
// velocity of force over almost no mass (it blows up); ziran gives quadrature particles a share
// of the mass, at the price of exact conservation. At the vertices every node that receives the
// term has the vertex's own share of mass there, as for a solid's particle, and momentum and
// angular momentum stay exact (tau = VP F^T is symmetric). Each vertex sums its elements in
// element order (the same bits for any thread count), then, where the material bends, its
// hinges' forces (codim/bending.h). For every element group of `groups`.
template <int Dim>
void codim_vertex_forces(const std::vector<MaterialParams>& materials,
                         std::vector<Particles<Dim>>* groups);

// The normal columns' stress of element e, VP_n F_n^T (VP in the element group's `stress`).
template <int Dim>
Mat<Dim> element_normal_stress(const Particles<Dim>& elements, size_t e);

// After G2P moved the vertices: each element's position, velocity and velocity gradient C at
// its vertices' means (the element's C is its corners' APIC C), the normal columns of F
// advected, d_n <- (I + dt C) d_n, and the tangent columns from the new edges. Element
// particles take no part in the grid transfers themselves.
template <int Dim>
void update_element_geometry(const Particles<Dim>& vertices, Real dt, Particles<Dim>* elements);

}  // namespace tear
