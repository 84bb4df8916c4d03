// Fuzz target: the OBJ mesh reader (decode_obj); what it reads must survive encode_obj and
// decode_obj again.
#include "fuzz_util.h"
#include "tear/io/mesh_io.h"

using namespace tear;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  TriMesh mesh;
  if (!fuzz::accepts([&] { mesh = decode_obj(fuzz::bytes_of(data, size)); })) return 0;
  TriMesh again;
  if (!fuzz::accepts([&] { again = decode_obj(encode_obj(mesh)); }))
    fuzz::finding("OBJ: the reader refuses what the writer wrote");
  if (again.triangles != mesh.triangles || again.vertices.size() != mesh.vertices.size())
    fuzz::finding("OBJ: the mesh changed in a round trip");
  for (size_t i = 0; i < mesh.vertices.size(); ++i)
    for (int a = 0; a < 3; ++a)
      if (!fuzz::same_value(mesh.vertices[i][a], again.vertices[i][a]))
        fuzz::finding("OBJ: vertex " + std::to_string(i) + " changed in a round trip");
  return 0;
}
