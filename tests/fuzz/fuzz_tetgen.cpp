// Fuzz target: the TetGen/Triangle reader (decode_tetgen); the input is the .node text, a NUL
// byte, then the .ele text (all of it .node where there is no NUL). What it reads must survive
// encode_volume_vtu and decode_volume_vtu.
#include "fuzz_util.h"
#include "tear/io/volume_mesh.h"

using namespace tear;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string bytes = fuzz::bytes_of(data, size);
  const size_t nul = bytes.find('\0');
  const std::string node = bytes.substr(0, nul);
  const std::string ele = nul == std::string::npos ? std::string() : bytes.substr(nul + 1);
  VolumeMesh m;
  if (!fuzz::accepts([&] { m = decode_tetgen(node, ele); })) return 0;
  check_volume_mesh(m);
  fuzz::check_volume_round_trip(m, "tetgen");
  return 0;
}
