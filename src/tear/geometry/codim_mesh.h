// geometry/: the meshes of codimensional bodies (Jiang et al. 2017): polylines of segments
// (yarn, hair, ropes) and triangle surfaces (cloth), in world space, with the generators a scene
// names (a sheet, a rope, hair strands on a scalp, a knit swatch) and the checks that refuse
// degenerate input. Knows nothing of particles, files or scenes.
#pragma once

#include "tear/math/types.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace tear {

struct CodimMesh {
  int manifold = 1;  // 1: segments (curves), 2: triangles (a surface)
  std::vector<Vec3d> vertices;
  // Vertex indices of each element: a segment uses the first two.
  std::vector<std::array<uint32_t, 3>> elements;
  size_t corners() const { return size_t(manifold + 1); }
};

// A rectangular sheet of size[0] x size[1] in the plane y = center.y (x along size[0], z along
// size[1]), resolution[0] x resolution[1] quads of two triangles each. Regular: the diagonals
// alternate in a checkerboard (the mesh has the square's symmetries for even resolutions);
// random: each quad's diagonal drawn at random and the interior vertices moved by up to a
// quarter of a quad in each direction, from `seed`.
CodimMesh make_sheet(const Vec3d& center, const double size[2], const int resolution[2],
                     bool random, uint64_t seed);

// A straight polyline of `segments` equal segments from `from` to `to`.
CodimMesh make_rope(const Vec3d& from, const Vec3d& to, int segments);

// `count` straight strands of `length` in `segments` segments each, rooted on the cap of the
// sphere (2D: the arc of the circle) of `radius` about `center` within `cap_deg` degrees of
// `direction`, each along the outward normal at its root: hair on a scalp. Roots on a
// golden-angle spiral over the cap (even cover, no randomness); 2D: evenly along the arc.
// Strand k's vertices are k (segments + 1) .. , root first. `dim` 2 keeps z = 0.
CodimMesh make_strands(const Vec3d& center, double radius, const Vec3d& direction, double cap_deg,
                       int count, double length, int segments, int dim);

// A stockinette knit swatch of size[0] x size[1] in the plane z = center.z (wales along x,
// courses along y), one yarn: `wales` loops of width W = size[0] / wales per course, each in
// `segments_per_loop` segments, the courses H = size[1] / courses apart, the yarn running back
// along every other course (flat knitting) and up the swatch's side between them in segments as
// long as the loops'. Course j follows, for
// t in [0, 2 pi wales],
//   x = W (t + 0.9 sin 2t) / (2 pi),  y = H (j + 3/4 cos t),  z = min(W, H) / 4 cos 2t:
// each loop's head (t = 0) bulges wider than its neck and reaches three quarters of the way
// into the next course, whose loops it crosses in the swatch's plane in front at some crossings
// and behind at others (interlocked, not lying side by side), a quarter of min(W, H) apart in
// depth where they cross.
CodimMesh make_knit(const Vec3d& center, const double size[2], int wales, int courses,
                    int segments_per_loop);

// Every vertex mapped by fn (a transform).
template <class Fn>
void transform_vertices(CodimMesh* mesh, Fn&& fn) {
  for (Vec3d& v : mesh->vertices) v = fn(v);
}

// The first defect of `mesh`, "" when none: a vertex that is not finite, two vertices at the
// same point, an element whose index is out of range or repeated, a zero-length segment or a
// zero-area triangle (relative to the mesh's size), a vertex no element uses, no elements at
// all. `dim` 2 also refuses a vertex off the z = 0 plane. The message names the vertex or element
// (0-based) and the reason: "triangle 12 has zero area (vertices 3, 4, 9)".
std::string find_mesh_defect(const CodimMesh& mesh, int dim);

}  // namespace tear
