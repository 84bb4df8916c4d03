// Fuzz target: the checkpoint reader (Simulation::decode_checkpoint) of a tiny 2D scene, made
// once. Each input is decoded as it is and again with its last 8 bytes replaced by the checksum
// of the rest, so that mutations get past the checksum to the fields behind it. A decoded state
// must give its frame table (or refuse with a std::exception: decode_checkpoint does not check
// the particle ids, rows_by_id does), then take a step and give its frame table again. The seeds
// (TearFuzzSeeds) are checkpoints of this build's format.
#include <memory>

#include "fuzz_util.h"
#include "tear/driver/simulation.h"
#include "tear/io/binary.h"

using namespace tear;

namespace {

// 16 particles: a 2x2-cell box at 4 particles a cell.
const char* const kScene = R"({
  "dim": 2,
  "grid": { "dx": 0.05, "domain_min": [0, 0], "domain_max": [0.5, 0.5] },
  "time": { "frame_dt": 0.01, "frames": 2 },
  "gravity": [0, -9.8],
  "materials": { "jelly": { "model": "neo_hookean", "E": 1000, "nu": 0.3, "rho": 2 } },
  "objects": [ { "shape": { "type": "box", "min": [0.2, 0.2], "max": [0.3, 0.3] },
                 "material": "jelly", "sampling": "grid" } ]
})";

Simulation& simulation() {
  static const std::unique_ptr<Simulation> sim =
      make_simulation(parse_scene(nlohmann::json::parse(kScene), "fuzz_checkpoint.json"));
  return *sim;
}

void decode(const std::string& bytes) {
  Simulation& sim = simulation();
  if (!fuzz::accepts([&] { sim.decode_checkpoint(bytes); })) return;
  size_t rows = sim.num_particles();
  fuzz::accepts([&] { rows = sim.frame_table().count; });
  if (rows != sim.num_particles())
    fuzz::finding("the frame table of a decoded checkpoint has another particle count");
  // A decoded state must step, or stop with a clear error (UnstableRun, a std::exception):
  // whatever F, C, damage or velocities the bytes gave its particles. One short step (the
  // step guard may redo it shorter, up to 2^8 times), then the frame table again.
  fuzz::accepts([&] { sim.step(1e-4); });
  fuzz::accepts([&] { rows = sim.frame_table().count; });
  if (rows != sim.num_particles())
    fuzz::finding("the frame table of a stepped checkpoint has another particle count");
}

// `bytes` with its last 8 bytes the checksum of the rest (binary.h).
std::string with_checksum(std::string bytes) {
  bytes.resize(bytes.size() - sizeof(uint64_t));
  append_checksum(&bytes);
  return bytes;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string bytes = fuzz::bytes_of(data, size);
  decode(bytes);
  if (bytes.size() >= sizeof(uint64_t)) decode(with_checksum(bytes));
  return 0;
}

extern "C" void TearFuzzSeeds(TearFuzzEmit emit) {
  auto put = [&](const char* name, const std::string& b) {
    emit(name, reinterpret_cast<const uint8_t*>(b.data()), b.size());
  };
  const std::unique_ptr<Simulation> sim =
      make_simulation(parse_scene(nlohmann::json::parse(kScene), "fuzz_checkpoint.json"));
  const std::string start = sim->encode_checkpoint();
  put("start.ckp", start);
  for (int i = 0; i < 3; ++i) sim->step(1e-3);
  const std::string stepped = sim->encode_checkpoint();
  put("stepped.ckp", stepped);
  put("truncated.ckp", stepped.substr(0, stepped.size() / 2));
  // The header: magic (8 bytes), dim, precision, groups (int32 each), then a uint64 count.
  std::string huge = stepped;
  const uint64_t count = uint64_t(1) << 60;
  huge.replace(20, sizeof(count), reinterpret_cast<const char*>(&count), sizeof(count));
  put("huge_count.ckp", with_checksum(huge));
  std::string groups = stepped;
  groups[16] = '\xff';
  put("many_groups.ckp", with_checksum(groups));
}
