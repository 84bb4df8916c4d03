// Fuzz target: the classic BGEO point reader (decode_bgeo); what it reads must survive
// encode_bgeo and decode_bgeo again.
#include "fuzz_util.h"
#include "tear/io/bgeo.h"

using namespace tear;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  PointTable t;
  if (!fuzz::accepts([&] { t = decode_bgeo(fuzz::bytes_of(data, size)); })) return 0;
  t.check_shape();
  fuzz::check_point_round_trip(t, encode_bgeo, decode_bgeo, "BGEO");
  return 0;
}
