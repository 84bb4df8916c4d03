// Fuzz target: the VTK XML unstructured-grid reader (decode_vtu); what it reads must survive
// encode_vtu and decode_vtu again.
#include "fuzz_util.h"
#include "tear/io/vtu.h"

using namespace tear;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  PointTable t;
  if (!fuzz::accepts([&] { t = decode_vtu(fuzz::bytes_of(data, size)); })) return 0;
  t.check_shape();
  fuzz::check_point_round_trip(t, encode_vtu, decode_vtu, "VTU");
  return 0;
}
