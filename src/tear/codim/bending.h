// codim/: optional bending stiffness of codimensional bodies (Jiang et al. 2017 have none; off
// unless a material sets bending_modulus). Energies of the mesh vertices' positions, on hinges
// derived from an element group (Particles::Hinges):
//  - curves: at each vertex joining exactly two segments, E = B / l (1 - t1 . t2), t1, t2 the
//    unit tangents of the segments, l the mean of their rest lengths, B = bending_modulus I the
//    rod's flexural rigidity (I = pi r^4 / 4; 2D, a strip of unit depth: (2 r)^3 / 12): for small
//    angles B theta^2 / (2 l), the discrete Euler-Bernoulli energy (B / 2) integral of kappa^2;
//  - surfaces: at each interior edge, the quadratic bending energy of Bergou et al. 2006 (Wardetzky
//    et al. 2007), E = D / (A_A + A_B) |K_0 x_0 + K_1 x_1 + K_2 x_2 + K_3 x_3|^2 / 2, K the rest
//    cotangent weights of the edge's two triangles, D = bending_modulus t^3 / (12 (1 - nu^2)) the
//    plate rigidity: (D / 2) integral of (kappa_1 + kappa_2)^2 for bendings that keep lengths,
//    zero for flat sheets in any rigid motion, constant Hessian.
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
// surface edge with other than two triangles, is no hinge.
template <int Dim>
void build_hinges(const std::vector<MaterialParams>& materials, const Particles<Dim>& vertices,
                  Particles<Dim>* el);

// Hinge h's energy at vertex positions x (the vertex group's, indexed as its vertices), its
// gradient with respect to its corners (g[slot]), and its Hessian on the corners' stacked
// coordinates (slot * Dim + component), projected onto positive semi-definite when `project`.
template <int Dim>
Real hinge_energy(const Particles<Dim>& el, size_t h, const Vec<Dim>* x);
template <int Dim>
void hinge_gradient(const Particles<Dim>& el, size_t h, const Vec<Dim>* x,
                    std::array<Vec<Dim>, 4>* g);
template <int Dim>
using HingeHessian = Eigen::Matrix<Real, 4 * Dim, 4 * Dim>;
template <int Dim>
HingeHessian<Dim> hinge_hessian(const Particles<Dim>& el, size_t h, const Vec<Dim>* x, bool project);

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
