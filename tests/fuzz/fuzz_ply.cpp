// Fuzz target: the PLY readers, points (decode_ply) and meshes (decode_mesh_ply), which share
// the header parser; what either reads must survive its writer and reader again.
#include "fuzz_util.h"
#include "tear/io/mesh_io.h"
#include "tear/io/ply.h"

using namespace tear;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string bytes = fuzz::bytes_of(data, size);
  PointTable t;
  if (fuzz::accepts([&] { t = decode_ply(bytes); })) {
    t.check_shape();
    fuzz::check_point_round_trip(
        t, [](const PointTable& table) { return encode_ply(table); }, decode_ply, "PLY");
  }
  TriMesh mesh;
  if (fuzz::accepts([&] { mesh = decode_mesh_ply(bytes); })) {
    TriMesh again;
    if (!fuzz::accepts([&] { again = decode_mesh_ply(encode_mesh_ply(mesh)); }))
      fuzz::finding("PLY mesh: the reader refuses what the writer wrote");
    if (again.triangles != mesh.triangles || again.vertices.size() != mesh.vertices.size())
      fuzz::finding("PLY mesh: the mesh changed in a round trip");
  }
  return 0;
}
