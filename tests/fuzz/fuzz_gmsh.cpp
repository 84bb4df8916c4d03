// Fuzz target: the gmsh MSH 4.1 reader (decode_gmsh, ASCII and binary); what it reads must
// survive encode_volume_vtu and decode_volume_vtu.
#include "fuzz_util.h"
#include "tear/io/volume_mesh.h"

using namespace tear;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  VolumeMesh m;
  if (!fuzz::accepts([&] { m = decode_gmsh(fuzz::bytes_of(data, size)); })) return 0;
  check_volume_mesh(m);
  fuzz::check_volume_round_trip(m, "gmsh");
  return 0;
}
