// Fuzz target: the STL mesh reader, binary and ascii (decode_stl); what it reads must survive
// encode_stl and decode_stl again.
#include "fuzz_util.h"
#include "tear/io/mesh_io.h"

using namespace tear;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  TriMesh mesh;
  if (!fuzz::accepts([&] { mesh = decode_stl(fuzz::bytes_of(data, size)); })) return 0;
  if (mesh.vertices.size() != 3 * mesh.triangles.size())
    fuzz::finding("STL: not three vertices of its own per triangle");
  TriMesh again;
  if (!fuzz::accepts([&] { again = decode_stl(encode_stl(mesh)); }))
    fuzz::finding("STL: the reader refuses what the writer wrote");
  if (again.triangles != mesh.triangles) fuzz::finding("STL: the mesh changed in a round trip");
  for (size_t i = 0; i < mesh.vertices.size(); ++i)
    for (int a = 0; a < 3; ++a)
      if (!fuzz::same_value(mesh.vertices[i][a], again.vertices[i][a]))
        fuzz::finding("STL: vertex " + std::to_string(i) + " changed in a round trip");
  return 0;
}
