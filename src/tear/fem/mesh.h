// fem/: the meshes of FEM bodies: linear tetrahedra (3D) or triangles (2D) over nodes, their
// checks (what tear check refuses, naming the element and the reason), quality figures, the
// boundary, and meshes made from tear's shapes by netgen (fem/mesher.h).
#pragma once

#include "tear/geometry/shape.h"
#include "tear/math/types.h"

#include <array>
#include <string>
#include <vector>

namespace tear {

struct FemMesh {
  int dim = 3;
  std::vector<Vec3d> nodes;                  // z = 0 in 2D
  std::vector<std::array<int, 4>> elements;  // node indices; a triangle's 4th is -1
  int corners() const { return dim + 1; }
};

// The signed volume (3D) or area (2D) of element e: positive for a tetrahedron whose corners 1, 2,
// 3 seen from corner 0 turn right-handed, a counter-clockwise triangle.
double element_volume(const FemMesh& m, size_t e);

// The mean-ratio quality of element e, in (0, 1]: 1 for the equilateral element,
// 12 (3 V)^(2/3) / sum of squared edges (3D), 4 sqrt(3) A / sum of squared edges (2D); 0 for a
// degenerate or inverted one.
double element_quality(const FemMesh& m, size_t e);

struct MeshFigures {
  size_t nodes = 0, elements = 0, boundary_faces = 0;
  double volume = 0;          // total
  double worst_quality = 0;   // element_quality, least
  size_t worst_element = 0;
  double smallest_height = 0; // least altitude of an element: what the explicit CFL uses
  double mean_edge = 0;
};

MeshFigures mesh_figures(const FemMesh& m);

// Throws std::runtime_error "NAME: element E ..." (0-based) for the first defect found: a node
// index out of range or repeated, a degenerate (quality under 1e-6) or inverted (negative
// volume) element, a face shared by more than two elements (non-manifold), a node no element
// uses, or elements in more than one connected piece (through shared nodes).
void check_fem_mesh(const FemMesh& m, const std::string& name);

// The boundary: the faces (3D: triangles, outward by the right-hand rule) or edges (2D: segments,
// the 3rd entry -1, the body on their left) that belong to one element, in element order.
std::vector<std::array<int, 3>> boundary_faces(const FemMesh& m);

// Turns every element of negative volume right way round (a mesher's or a file's convention).
void orient_elements(FemMesh* m);

// A mesh of the shape (world space) with edges of about `h`, made by netgen: 3D boxes, spheres,
// cylinders and closed triangle meshes; 2D boxes, disks and tubes (annuli). Deterministic: the
// same shape and h give the same mesh. Throws std::invalid_argument for a shape it cannot mesh
// (saying which can be) and std::runtime_error where netgen fails.
FemMesh mesh_shape(const Shape& shape, int dim, double h);

}  // namespace tear
