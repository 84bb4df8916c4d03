// scene/: flow fibers (paper §7, Figs. 6, 9, 14): the directions of a potential flow through a
// body from its sources to its sinks. On the cells of a grid over the shape, the potential phi
// solves Laplace's equation with phi = 1 near the sources, 0 near the sinks and no flux
// through the shape's boundary; a fiber is -grad phi, normalised: unit length, tangent to the
// boundary, from the sources to the sinks. The paper simulates a fluid instead; the potential
// flow gives the same kind of streamlines without a fluid solver.
#pragma once

#include "tear/geometry/shape.h"

#include <vector>

namespace tear {

class FlowField {
 public:
  // Solves for the potential on cells of side h over `shape` (dim 2 or 3). Cells whose centre
  // lies within `radius` of a source (sink) are held at 1 (0); a source or sink near no cell of
  // the shape throws std::runtime_error naming it ("source 0 (x, y) ...").
  FlowField(const Shape& shape, int dim, double h, const std::vector<Vec3d>& sources,
            const std::vector<Vec3d>& sinks, double radius);

  // The unit flow direction at p: within `radius` of a source, away from it; of a sink,
  // towards it; elsewhere -grad phi interpolated from the cells of the shape around p; or
  // `fallback` where the flow does not reach (a part cut off from every source and sink) or
  // stands still.
  Vec3d direction(const Vec3d& p, const Vec3d& fallback) const;

  // The potential of the cell holding p (NaN outside the shape's cells), for tests.
  double potential(const Vec3d& p) const;
  int iterations() const { return iterations_; }

 private:
  long cell_of(const Vec3d& p) const;  // -1 outside the grid
  int dim_;
  double h_;
  Vec3d lo_;
  int n_[3] = {1, 1, 1};
  std::vector<char> inside_;   // the cell's centre is in the shape
  std::vector<double> phi_;    // NaN: cut off from every source and sink
  std::vector<Vec3d> grad_;    // per cell, central differences where both neighbours are in
  int iterations_ = 0;
  std::vector<Vec3d> sources_, sinks_;
  double radius_ = 0;
};

}  // namespace tear
