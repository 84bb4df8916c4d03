// particles/: the structure-of-arrays particle store.
// Owns per-particle state and its reordering; knows nothing of grids, materials or scenes.
#pragma once

#include "tear/math/types.h"

#include <cstdint>
#include <vector>

namespace tear {

template <int Dim>
struct Particles {
  std::vector<Vec<Dim>> x;      // position
  std::vector<Vec<Dim>> v;      // velocity
  std::vector<Mat<Dim>> C;      // APIC affine velocity matrix (velocity gradient estimate)
  std::vector<Mat<Dim>> F;      // deformation gradient
  std::vector<Mat<Dim>> fiber;  // rest fiber frame D = [a1 a2 (a3)], orthonormal columns
  std::vector<Real> mass;
  std::vector<Real> vol0;       // rest volume
  std::vector<Real> damage;     // phase-field damage d in [0, 1], never decreasing
  std::vector<Real> drive;      // crack driving force history Dtilde^H, never decreasing
  std::vector<uint32_t> id;     // stable identity across reorderings
  std::vector<uint16_t> material;

  size_t size() const { return x.size(); }
  void resize(size_t n);
  // Append one particle at rest (F = I, C = 0, d = 0).
  void push_back(const Vec<Dim>& pos, const Vec<Dim>& vel, const Mat<Dim>& frame, Real m,
                 Real v0, uint16_t mat);
  // Reorder every array: new index k holds old particle order[k].
  void permute(const std::vector<uint32_t>& order);
  // Bytes of state per particle (for memory estimates and benchmarks).
  static constexpr size_t bytes_per_particle() {
    return sizeof(Vec<Dim>) * 2 + sizeof(Mat<Dim>) * 3 + sizeof(Real) * 4 + sizeof(uint32_t) +
           sizeof(uint16_t);
  }
};

}  // namespace tear
