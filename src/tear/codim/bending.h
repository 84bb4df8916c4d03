// codim/: optional bending stiffness of codimensional bodies (Jiang et al. 2017 have none; off
// unless a material sets bending_modulus). Energies of the mesh vertices' positions, on hinges
// derived from an element group (Particles::Hinges):
//  - curves: at each vertex joining exactly two segments, E = B / l (1 - t1 . t2), t1, t2 the
//    unit tangents of the segments, l the mean of their rest lengths, B = bending_modulus I the
//    rod's flexural rigidity (I = pi r^4 / 4; 2D, a strip of unit depth: (2 r)^3 / 12): for small
//    angles B theta^2 / (2 l), the discrete Euler-Bernoulli energy (B / 2) integral of kappa^2;
//  - surfaces: at each interior vertex i (every edge round it between two triangles), the
//    vertex-based quadratic energy of Wardetzky et al. 2007, E = D / (2 A_i) |sum_j w_ij
//    (x_j - x_i)|^2, w_ij = (cot a_ij + cot b_ij) / 2 the rest cotangent weights of its ring and
//    A_i its mixed Voronoi rest area (Meyer et al. 2003): the cotangent Laplacian is A_i (kappa_1 + kappa_2)
//    n, so E -> (D / 2) integral of (kappa_1 + kappa_2)^2 for bendings that keep lengths, with
//    D = bending_modulus t^3 / (12 (1 - nu^2)) the plate rigidity. Zero for flat sheets in any
//    rigid motion; constant Hessian. (The edge-based form of Bergou et al. 2006 was measured 30-40
//    % too stiff on randomly triangulated sheets and not converging; this one converges on
//    both, tests/mpm/codim_bending_test.cpp.)
// The rest shape of bending is straight (curves) and flat (surfaces): a mesh given curved is
// pulled towards straight or flat (docs/materials.md). Knows nothing of grids or scenes.
#pragma once

#include "tear/materials/material.h"
#include "tear/particles/particles.h"

#include <array>
#include <vector>

namespace tear {

// Whether element group `el`'s material bends.
template <int Dim>
bool bends(const std::vector<MaterialParams>& materials, const Particles<Dim>& el);

// Builds el->hinges (once: until `built` is reset) from its connectivity, rest state and
// materials; `vertices` is its vertex group. A curve vertex with other than two segments, and a
// surface vertex on the border (or by an edge of other than two triangles), is no hinge.
template <int Dim>
void build_hinges(const std::vector<MaterialParams>& materials, const Particles<Dim>& vertices,
                  Particles<Dim>* el);

// Hinge h's energy at vertex positions x (the vertex group's, indexed as its vertices), and its
// gradient with respect to its corners (g[0 .. corners(h)), in corner order).
template <int Dim>
Real hinge_energy(const Particles<Dim>& el, size_t h, const Vec<Dim>* x);
template <int Dim>
void hinge_gradient(const Particles<Dim>& el, size_t h, const Vec<Dim>* x, Vec<Dim>* g);

// A curve hinge's Hessian on its three corners' stacked coordinates (corner * Dim + component),
// projected onto positive semi-definite when `project`.
template <int Dim>
using CurveHingeHessian = Eigen::Matrix<Real, 3 * Dim, 3 * Dim>;
template <int Dim>
CurveHingeHessian<Dim> curve_hinge_hessian(const Particles<Dim>& el, size_t h, const Vec<Dim>* x,
                                           bool project);

// y[c] = (H u)[c] over hinge h's corners c, u the vertices' (indexed as x is), H the hinge's
// Hessian: a surface's constant one, or `curve` (from curve_hinge_hessian) for a curve's. And
// H's diagonal entries at corner c.
template <int Dim>
void hinge_hessian_product(const Particles<Dim>& el, size_t h, const CurveHingeHessian<Dim>* curve,
                           const Vec<Dim>* u, Vec<Dim>* y);
template <int Dim>
Vec<Dim> hinge_hessian_diagonal(const Particles<Dim>& el, size_t h,
                                const CurveHingeHessian<Dim>* curve, uint32_t c);

// Adds -dE/dx of every hinge of `el` to its vertices' `force` (each vertex sums its hinges in
// hinge order: the same bits on any thread count).
template <int Dim>
void add_bending_forces(const Particles<Dim>& el, Particles<Dim>* vertices);

// The frequency of the stiffest bending mode the grid resolves, omega = pi^2 sqrt(B / (rho A)) /
// h^2 with h the larger of the element's size and dx, as a wave speed omega dx / 2 for the
// explicit step's limit (dt <= cfl dx / c); 0 without bending.
template <int Dim>
Real bending_wave_speed(const std::vector<MaterialParams>& materials, const Particles<Dim>& el,
                        double dx);

}  // namespace tear
