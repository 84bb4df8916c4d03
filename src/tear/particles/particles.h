// particles/: the structure-of-arrays particle store of one group. Every field is declared
// once below; resize, append, permute, checkpoints, frame columns and memory figures follow
// from the declarations (particles/field.h). Knows nothing of grids, materials or scenes.
#pragma once

#include "tear/math/types.h"
#include "tear/particles/field.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace tear {

// What a group's particles are (Jiang et al. 2017 supplement, particles of types (i)-(iii)):
//  - Volumetric: samples of a solid, each with its own F.
//  - MeshVertices: the vertices of codimensional meshes (curves, surfaces): mass, x, v and the
//    APIC C, moved by the grid; they carry their elements' in-manifold force (`force`) and
//    shares of their normal stress (`stress`) to the grid. F is unused (the identity).
//  - CurveElements, SurfaceElements: one quadrature particle per segment or triangle, at its
//    centroid: the element's vertices (`element_vertices`, indices into the group
//    `vertex_group`), its rest D^-1 (`rest_inverse`), F = [d1 (d2) | normals] D^-1 with the
//    tangent columns from the vertices and the normals advected by their vertices' velocity
//    gradient, the elastic volume `vol0` and no mass (codim/elements.h says why). They take no
//    part in the grid transfers: their vertices carry their forces.
// Codimensional groups are never reordered in memory (elements refer to vertices by index).
enum class GroupKind { Volumetric, MeshVertices, CurveElements, SurfaceElements };

// The manifold dimension of an element group's elements (1, 2), 0 for the others.
inline int element_dimension(GroupKind kind) {
  return kind == GroupKind::CurveElements ? 1 : kind == GroupKind::SurfaceElements ? 2 : 0;
}

// One particle group. Frame files list the columns in declaration order: id, x y z, vx vy vz,
// damage, material, fx fy fz (ARCHITECTURE.md "Outputs"), then the optional columns a run asks
// for (scene output.fields): driving_force, damage_laplacian.
template <int Dim>
struct Particles : FieldRegistry {
  using V = Vec<Dim>;
  using M = Mat<Dim>;

  GroupKind kind = GroupKind::Volumetric;
  // Element groups: the index of their vertices' group in the state's groups (-1: none).
  int vertex_group = -1;

  // Stable identity across reorderings: 0..n-1 in sampling order.
  Field<uint32_t> id{this, state_field("id", {{"id"}, ColumnType::Int32}), 0};
  Field<V> x{this, state_field("x", {{"x", "y", "z"}, ColumnType::Float32}), V::Zero()};
  Field<V> v{this, state_field("v", {{"vx", "vy", "vz"}, ColumnType::Float32}), V::Zero()};
  // Phase-field damage d in [0, 1], never decreasing.
  Field<Real> damage{this, state_field("damage", {{"damage"}, ColumnType::Float32}), 0};
  Field<uint16_t> material{this, state_field("material", {{"material"}, ColumnType::UInt8}), 0};
  // World-space fiber direction: the deformed primary fiber F a1, normalised.
  DerivedColumns world_fiber{this, {{"fx", "fy", "fz"}, ColumnType::Float32}, &world_fiber_of};
  // APIC affine velocity matrix (velocity gradient estimate).
  Field<M> C{this, state_field("C"), M::Zero()};
  // Deformation gradient.
  Field<M> F{this, state_field("F"), M::Identity()};
  // Rest fiber frame D = [a1 a2 (a3)], orthonormal columns. Optional, on in a new store: the
  // sampler turns it off where every frame is the identity (an isotropic body, or anisotropic
  // along x), saving 72 bytes a particle in 3D in every reorder; read it through fiber_of().
  Field<M> fiber{this, optional_state_field("fiber"), M::Identity()};
  Field<Real> mass{this, state_field("mass"), 0};
  Field<Real> vol0{this, state_field("vol0"), 0};  // rest volume
  // Crack driving force history Dtilde^H, never decreasing: only where damage is simulated.
  Field<Real> drive{this, optional_state_field("drive"), 0};
  // Plastic state, only where some material is plastic (materials/plasticity.h): the
  // accumulated equivalent plastic strain (a frame column), and the volume Drucker-Prager's
  // volume correction owes back.
  Field<Real> plastic_strain{
      this, optional_state_field("plastic_strain", {{"plastic_strain"}, ColumnType::Float32}), 0};
  Field<Real> plastic_volume{this, optional_state_field("plastic_volume"), 0};
  // The tension of the inextensibility constraint along the fiber (Pa), only where some
  // material is inextensible (mpm/inextensibility.h): a frame column.
  Field<Real> fiber_tension{
      this, optional_state_field("fiber_tension", {{"fiber_tension"}, ColumnType::Float32}), 0};
  // Home block slot at the last reorder (-1: never reordered); the reorder decision, and so the
  // summation order, depends on it, so it is part of the restartable state.
  Field<int32_t> reorder_slot{this, state_field("reorder_slot"), -1};
  // This step's undegraded first Piola stress P(F) and J = det F (the constitutive phase; only
  // where a step has one, mpm/phases.h has_stress_phase: otherwise P2G computes the stress as
  // it goes).
  Field<M> stress{this, optional_scratch_field("stress"), M::Zero()};
  Field<Real> J{this, optional_scratch_field("J"), 1};
  // This step's damage gradient, where crack fields are split (mpm/crack_fields.cpp).
  Field<V> damage_gradient{this, optional_scratch_field("damage_gradient"), V::Zero()};
  // Optional frame columns. The crack driving force the damage update used, Dtilde (`drive`;
  // 0 where damage is not simulated).
  DerivedColumns driving_force{
      this, {{"driving_force"}, ColumnType::Float32}, &driving_force_of, true};
  // The damage Laplacian (L d)_p the damage update took this step (damage/phase_field.h; with
  // an anisotropic crack surface, M_p : grad grad d): state, so that it stays with its particle
  // through reorders and migrations until the frame is written.
  Field<Real> damage_laplacian{
      this, optional_state_field("damage_laplacian", {{"damage_laplacian"}, ColumnType::Float32}),
      0};

  // Codimensional groups (GroupKind): an element's vertex indices (segments use the first two),
  // its rest D^-1 (block diagonal: the tangents' rest edges inverted, identity on the normals),
  // and what its friction return map found (ContactState of materials/material.h: a frame
  // column); a vertex's in-manifold force, made every step before P2G.
  Field<std::array<uint32_t, 3>> element_vertices{this, optional_state_field("element_vertices"),
                                                  {0, 0, 0}};
  Field<M> rest_inverse{this, optional_state_field("rest_inverse"), M::Identity()};
  Field<uint8_t> contact{this, optional_state_field("contact", {{"contact"}, ColumnType::UInt8}),
                         0};
  Field<V> force{this, optional_scratch_field("force"), V::Zero()};
  // Element groups: each corner's share of the element's normal-column stress (codim/).
  Field<M> normal_stress{this, optional_scratch_field("normal_stress"), M::Zero()};
  // Element groups' frame column: how far the normal is from rest, r33 of F = Q R for a surface
  // (1 apart, < 1 pressed against a layer, < 0 inverted), the cross-section's area r22 r33 (3D)
  // or r22 (2D) for a curve.
  DerivedColumns normal_stretch{this, {{"normal_stretch"}, ColumnType::Float32},
                                &normal_stretch_of, true};

  Particles() { enable("fiber"); }
  // A group of another kind, with the optional fields the kind needs (fiber off).
  explicit Particles(GroupKind group_kind);

  bool codimensional() const { return kind != GroupKind::Volumetric; }

  // Mesh vertices: the (element, corner) pairs of each vertex, element * corners + corner, for
  // vertex v at incident[incident_begin[v] .. incident_begin[v + 1]), in element order. Derived
  // from the element group's element_vertices by codim_vertex_forces (rebuilt where the sizes
  // do not match); not state, not a field.
  std::vector<uint32_t> incident_begin, incident;

  // Element groups whose material bends (codim/bending.h): the hinges, each a stencil of
  // vertices (a curve's interior vertex with its two neighbours; a surface's interior vertex with
  // its one-ring), indices local to the vertex group. Derived by codim/bending.h from the
  // elements, their rest state and the materials (built when `built` is false); not state, not
  // a field.
  struct Hinges {
    bool built = false;
    std::vector<uint32_t> begin;    // hinge h's corners: corner[begin[h] .. begin[h + 1])
    std::vector<uint32_t> corner;   // curves: a, b (the hinge), c; surfaces: the vertex, its ring
    std::vector<Real> weight;       // per corner; surfaces: the cotangent Laplacian's row
    std::vector<Real> stiffness;    // curves: B / mean rest length; surfaces: D / vertex area
    std::vector<uint32_t> vertex_begin, incident;  // per vertex: its positions in corner[], hinge order
    size_t size() const { return stiffness.size(); }
    uint32_t corners(size_t h) const { return begin[h + 1] - begin[h]; }
  } hinges;

  // The optional frame columns a run may ask for (scene output.fields): the solids' ones. The
  // element groups' own (contact, normal_stretch) are written in every frame's mesh parts.
  std::vector<std::string> requestable_columns() const;

  // Append one particle at rest (F = I, C = 0, d = 0) with id = its index. A frame other than
  // the identity turns the fiber field on.
  void push_back(const V& pos, const V& vel, const M& frame, Real m, Real v0, uint16_t mat);

  // Particle i's rest fiber frame: the identity where the fiber field is off.
  const M& fiber_of(size_t i) const { return fiber.empty() ? kIdentity : fiber[i]; }
  // Turn the fiber field off where every frame is exactly the identity (results are the same
  // bits either way: fiber_of() gives the identity); returns whether it did.
  bool drop_identity_fibers();

 private:
  inline static const M kIdentity = M::Identity();
  // Bit for bit (a -0 entry is not the identity's 0: fiber_of() must give the same bits).
  static bool is_identity(const M& frame);
  static void world_fiber_of(const FieldRegistry& store, size_t i, double* out);
  static void driving_force_of(const FieldRegistry& store, size_t i, double* out);
  static void normal_stretch_of(const FieldRegistry& store, size_t i, double* out);
};

}  // namespace tear
