// fem/: the Lagrangian FEM simulation of solid bodies meshed with linear tetrahedra (3D) or
// triangles (2D): nodes with lumped mass, elements with their rest shape, the materials of
// materials/ on each element's F, the explicit (symplectic Euler) and implicit (backward Euler,
// Newton on the incremental potential) integrators, gravity, and contact of nodes with the
// domain walls and colliders of grid/collider.h. Knows no scene (docs/fem.md).
#pragma once

#include "tear/fem/mesh.h"
#include "tear/materials/material.h"
#include "tear/materials/plasticity.h"
#include "tear/mpm/settings.h"
#include "tear/mpm/time_step.h"
#include "tear/particles/particles.h"

#include <array>
#include <functional>
#include <memory>
#include <vector>

namespace tear {

// The elements of every body, in body order: corners (indices into the nodes), the inverse of
// the elastic rest shape (F = D_s rest_inverse, D_s the edges from corner 0: D_m^-1 of the
// mesh, times F_p^-1 once a plastic element has yielded), rest volume, material, rest fiber
// frame, Rayleigh stiffness damping beta (s) and plastic state. Fixed for a run but for
// rest_inverse and plastic, which plasticity changes (and checkpoints keep).
template <int Dim>
struct FemElements {
  using Corners = std::array<uint32_t, Dim + 1>;
  std::vector<Corners> corners;
  std::vector<Mat<Dim>> rest_inverse;
  std::vector<Real> vol0;
  std::vector<uint16_t> material;
  std::vector<Mat<Dim>> fiber;
  std::vector<Real> stiffness_damping;
  std::vector<PlasticState> plastic;
  // Consistent mass (ElementSetup::consistent_mass): c = rho V / ((Dim + 1) (Dim + 2)), the
  // element's mass matrix being c (1 + delta_ab) I over its corners; 0: lumped only.
  std::vector<Real> mass_coupling;
  size_t size() const { return corners.size(); }
};

// One body's share of the nodes and elements.
struct FemBody {
  size_t node_begin = 0, node_end = 0, element_begin = 0, element_end = 0;
  size_t face_begin = 0, face_end = 0;  // its boundary faces in FemState::faces
  MeshFigures figures;                  // of its mesh at rest (mesh_figures)
};

// What the implicit solve did, summed since the last reset (FrameStats' implicit figures).
struct FemSolveStats {
  long solves = 0, newton_iterations = 0, cg_iterations = 0, unconverged = 0;
  int newton_iterations_max = 0;
  double residual_max = 0;
};

template <int Dim>
class FemAssembly;  // the implicit solve's sparse matrix and its factor (fem.cpp)

template <int Dim>
struct FemState {
  // The nodes as a group of mesh vertices (id, x, v, mass, material: the field registry writes
  // their frames and checkpoints). Never reordered: elements refer to them by index.
  Particles<Dim> nodes{GroupKind::MeshVertices};
  FemElements<Dim> elements;
  std::vector<FemBody> bodies;
  std::vector<std::array<int, 3>> faces;  // every body's boundary (mesh.h), node indices
  // Per node, the (element, corner) pairs that touch it, element * (Dim + 1) + corner, in
  // element order: the gather of element forces in a fixed order.
  std::vector<uint32_t> incident_begin, incident;
  // Rayleigh damping (docs/fem.md): per node, alpha m (kg/s) summed over its elements' shares;
  // `damped`: some element has alpha or beta.
  std::vector<Real> mass_damping;
  bool damped = false;
  // The largest beta of any element and alpha (mass_damping / mass) of any node: the explicit
  // step's damping limit (fem_dt_limits), fixed once the bodies are made.
  Real stiffness_damping_max = 0, mass_damping_rate_max = 0;
  bool consistent = false;  // some element has consistent mass (the implicit integrator only)
  double smallest_height = 0;  // of all elements at rest (mesh_figures)
  double time = 0;
  long steps = 0;
  std::shared_ptr<FemAssembly<Dim>> assembly;  // built by the first implicit step
  size_t num_nodes() const { return nodes.size(); }
};

// What a body's element is made of: its material (an index into the materials), rest fiber
// frame and Rayleigh damping: the force -(alpha M + beta K) v, alpha in 1/s (mass), beta in s
// (stiffness; K the projected stiffness at the step's start).
template <int Dim>
struct ElementSetup {
  uint16_t material = 0;
  Mat<Dim> fiber = Mat<Dim>::Identity();
  Real mass_damping = 0, stiffness_damping = 0;
  // The consistent mass matrix rho V / ((Dim + 1) (Dim + 2)) (1 + delta_ab) instead of the
  // lumped rho V / (Dim + 1) at each corner, in the implicit integrator's inertia (docs/fem.md).
  // The nodes' masses (momentum, gravity, contact) stay the lumped row sums, which are equal.
  bool consistent_mass = false;
};

// Append a body: the mesh's nodes (lumped mass: rho V / (Dim + 1) of each element at each of its
// corners), its elements with setup(centroid, element index within the body), moving with
// velocity + omega x (x - centre) (omega about z in 2D). The mesh must pass check_fem_mesh. A
// node's material (a frame column) is that of its first element.
template <int Dim>
void append_fem_body(const FemMesh& mesh, const std::vector<MaterialParams>& materials,
                     const std::function<ElementSetup<Dim>(const Vec3d&, size_t)>& setup,
                     const Vec3d& velocity, const Vec3d& angular_velocity, const Vec3d& centre,
                     FemState<Dim>* state);

// Elastic energy of the nodes at positions x, and its gradient (dE/dx per node; nodes in node
// order, Dim entries each).
template <int Dim>
double fem_elastic_energy(const MpmSettings& s, const FemState<Dim>& state,
                          const std::vector<Vec<Dim>>& x);
template <int Dim>
void fem_elastic_gradient(const MpmSettings& s, const FemState<Dim>& state,
                          const std::vector<Vec<Dim>>& x, std::vector<Vec<Dim>>* gradient);
// Element e's Hessian of its elastic energy at x (the projected stress derivative:
// positive semi-definite), (Dim (Dim + 1))^2, corners in order, each corner's Dim rows.
template <int Dim>
Eigen::MatrixXd fem_element_hessian(const MpmSettings& s, const FemState<Dim>& state,
                                    const std::vector<Vec<Dim>>& x, size_t e);
// F of element e at x.
template <int Dim>
Mat<Dim> fem_deformation(const FemState<Dim>& state, const std::vector<Vec<Dim>>& x, size_t e);

// The step's limits: max_dt, the elastic wave across the smallest element (explicit only), the
// nodes' speed (cfl dx / max |v|: contact's scale, dx = s.dx).
template <int Dim>
DtLimits fem_dt_limits(const MpmSettings& s, const FemState<Dim>& state);

// Plasticity (s.material_plasticity): each element of a plastic material whose elastic F lies
// outside its yield surface is returned to it (materials/plasticity.h, as MPM particles are),
// and its elastic rest shape follows: rest_inverse = D_s^-1 F', so that F = F' at the nodes'
// positions. The energy stays V0 Psi(F_e) over the mesh's rest volume. Run at the end of every
// step; returns the number of elements that yielded.
template <int Dim>
size_t fem_plastic_flow(const MpmSettings& s, FemState<Dim>* state);

// Whether an element of some material is plastic.
bool fem_plastic(const MpmSettings& s);

// One step of dt: explicit or implicit by s.integrator, then fem_plastic_flow. Returns dt.
// Throws std::invalid_argument for an explicit step of a state with consistent mass.
template <int Dim>
double fem_step(const MpmSettings& s, FemState<Dim>* state, double dt, FemSolveStats* stats);

struct FemFigures {
  double mass = 0, kinetic_energy = 0, elastic_energy = 0;
  Vec3d momentum = Vec3d::Zero(), angular_momentum = Vec3d::Zero();  // about the origin
};
template <int Dim>
FemFigures measure_fem(const MpmSettings& s, const FemState<Dim>& state);

// What each element holds at the nodes' positions, for the frames' volume mesh: strain energy
// density Psi (J/m^3), the von Mises stress of the Cauchy stress sigma = P F^T / J (Pa; 0 where
// J <= 0), J = det F, the current direction of its first fiber, F a1 / |F a1| (z = 0 in 2D),
// and the equivalent plastic strain.
struct FemElementFigures {
  std::vector<double> energy, von_mises, J;
  std::vector<double> plastic_strain;  // equivalent plastic strain (PlasticState::strain)
  std::vector<Vec3d> fiber;
};
template <int Dim>
FemElementFigures fem_element_figures(const MpmSettings& s, const FemState<Dim>& state);

// Bytes held by the nodes, elements, incidence and the implicit solve's matrix and factor.
template <int Dim>
size_t fem_memory_bytes(const FemState<Dim>& state);

// The first node whose position or velocity is not finite, or that is outside the domain; -1:
// none.
template <int Dim>
long find_fem_fault(const MpmSettings& s, const FemState<Dim>& state);

}  // namespace tear
