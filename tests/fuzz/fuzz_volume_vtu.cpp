// Fuzz target: the volume-mesh VTU reader (decode_volume_vtu); what it reads, columns included,
// must survive encode_volume_vtu and decode_volume_vtu again.
#include "fuzz_util.h"
#include "tear/io/volume_mesh.h"

using namespace tear;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  VolumeMesh m;
  if (!fuzz::accepts([&] { m = decode_volume_vtu(fuzz::bytes_of(data, size)); })) return 0;
  check_volume_mesh(m);
  fuzz::check_volume_round_trip(m, "volume VTU");
  return 0;
}
