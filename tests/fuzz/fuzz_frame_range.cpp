// Fuzz target: the --frames range parser (parse_frame_range); an accepted range is well formed.
#include "fuzz_util.h"
#include "tear/io/frames.h"

using namespace tear;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  FrameRange r;
  if (!fuzz::accepts([&] { r = parse_frame_range(fuzz::bytes_of(data, size)); })) return 0;
  if (r.first < 0 || r.last < -1 || (r.last >= 0 && r.last < r.first))
    fuzz::finding("parse_frame_range accepted the range " + std::to_string(r.first) + ":" +
                  std::to_string(r.last));
  return 0;
}
