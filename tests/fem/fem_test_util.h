// Shared by the FEM tests: meshes that need no mesher.
#pragma once

#include "tear/driver/simulation.h"
#include "tear/fem/mesh.h"
#include "tear/scene/scene.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <memory>
#include <string>

namespace tear::test {

// A box [lo, hi] split into n cells per unit of `cells`, each cell into 6 tetrahedra (Kuhn) or
// 2 triangles: a structured mesh that needs no mesher.
inline FemMesh structured_box(int dim, const Vec3d& lo, const Vec3d& hi, const std::array<int, 3>& n) {
  FemMesh m;
  m.dim = dim;
  const int nz = dim == 3 ? n[2] : 0;
  const auto id = [&](int i, int j, int k) { return (k * (n[1] + 1) + j) * (n[0] + 1) + i; };
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= n[1]; ++j)
      for (int i = 0; i <= n[0]; ++i) {
        Vec3d x = lo;
        x.x() += (hi.x() - lo.x()) * i / n[0];
        x.y() += (hi.y() - lo.y()) * j / n[1];
        if (dim == 3) x.z() += (hi.z() - lo.z()) * k / nz;
        m.nodes.push_back(x);
      }
  for (int k = 0; k < std::max(nz, 1); ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        if (dim == 2) {
          m.elements.push_back({id(i, j, 0), id(i + 1, j, 0), id(i + 1, j + 1, 0), -1});
          m.elements.push_back({id(i, j, 0), id(i + 1, j + 1, 0), id(i, j + 1, 0), -1});
          continue;
        }
        // The six tetrahedra around the diagonal from corner 0 to corner 7.
        int c[8];
        for (int b = 0; b < 8; ++b) c[b] = id(i + (b & 1), j + ((b >> 1) & 1), k + ((b >> 2) & 1));
        const int paths[6][2] = {{1, 3}, {1, 5}, {2, 3}, {2, 6}, {4, 5}, {4, 6}};
        for (const auto& p : paths) m.elements.push_back({c[0], c[p[0]], c[p[0] | p[1]], c[7]});
      }
  orient_elements(&m);
  return m;
}

// Runs `frames` frames of the scene straight through and again resumed from a checkpoint after
// half of them, expecting the same final checkpoint bytes. Returns the straight run; *mid gets
// the checkpoint.
inline std::unique_ptr<Simulation> expect_resumes_identically(const Scene& s, int frames,
                                                              std::string* mid) {
  auto whole = make_simulation(s);
  for (int f = 0; f < frames; ++f) whole->advance_frame();
  auto first = make_simulation(s);
  for (int f = 0; f < frames / 2; ++f) first->advance_frame();
  *mid = first->encode_checkpoint();
  auto second = make_simulation(s);
  second->decode_checkpoint(*mid);
  for (int f = frames / 2; f < frames; ++f) second->advance_frame();
  EXPECT_EQ(whole->encode_checkpoint(), second->encode_checkpoint());
  return whole;
}

}  // namespace tear::test
