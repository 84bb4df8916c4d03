// tests/fuzz: what every fuzz target shares. A target feeds its input to one reader; the
// reader's rejections are std::exceptions (caught here); anything else is a finding.
#pragma once

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <cstring>
#include <string>

#include "tear/io/point_table.h"
#include "tear/io/volume_mesh.h"

namespace tear::fuzz {

inline std::string bytes_of(const uint8_t* data, size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

// Runs `f`, ignoring the std::exception with which a reader rejects bad input. Returns whether
// `f` finished without one.
template <class F>
bool accepts(F&& f) {
  try {
    f();
    return true;
  } catch (const std::exception&) {
    return false;
  }
}

// A property that must hold broke: abort, which libFuzzer and the replay both report as a crash.
[[noreturn]] inline void finding(const std::string& what) {
  std::fprintf(stderr, "fuzz finding: %s\n", what.c_str());
  std::abort();
}

// Whether two values are the same number (NaNs equal, as a file keeps them).
inline bool same_value(double a, double b) { return a == b || (a != a && b != b); }

// The values of `u` are those of `t` wherever the two have the same names and types.
inline void check_same_columns(const PointTable& t, const PointTable& u, const char* format) {
  if (u.names != t.names || u.types != t.types) return;
  for (size_t c = 0; c < t.names.size(); ++c)
    for (size_t i = 0; i < t.count; ++i)
      if (!same_value(t.columns[c][i], u.columns[c][i]))
        finding(std::string(format) + ": column '" + t.names[c] + "' row " + std::to_string(i) +
                " changed in a round trip");
}

// What a point writer writes its reader must read: `encode` of a table that `decode` returned,
// decoded again, must give the same values wherever the writer kept the columns' names and types
// (BGEO and VTU group x y z, vx vy vz, fx fy fz into vector attributes, always float, so names
// and types may change).
template <class Encode, class Decode>
void check_point_round_trip(const PointTable& t, Encode encode, Decode decode,
                            const char* format) {
  std::string bytes;
  if (!accepts([&] { bytes = encode(t); })) return;  // a table the writer refuses
  PointTable u;
  try {
    u = decode(bytes);
  } catch (const std::exception& e) {
    finding(std::string(format) + ": the reader refuses what the writer wrote: " + e.what());
  }
  if (u.count != t.count) finding(std::string(format) + ": the point count changed");
  check_same_columns(t, u, format);
}

// What a volume mesh reader returns the VTU writer must write and decode_volume_vtu read back
// as the same mesh: dimension, nodes and cells exactly (Float64 points, Int64 cells), and the
// columns' values wherever their names and types came back the same.
inline void check_volume_round_trip(const VolumeMesh& m, const char* format) {
  std::string bytes;
  try {
    bytes = encode_volume_vtu(m);
  } catch (const std::exception& e) {
    finding(std::string(format) + ": the VTU writer refuses what the reader returned: " + e.what());
  }
  VolumeMesh u;
  try {
    u = decode_volume_vtu(bytes);
  } catch (const std::exception& e) {
    finding(std::string(format) + ": decode_volume_vtu refuses what encode_volume_vtu wrote: " +
            e.what());
  }
  if (u.dim != m.dim || u.nodes != m.nodes || u.cells != m.cells)
    finding(std::string(format) + ": the mesh changed in a VTU round trip");
  check_same_columns(m.node_columns, u.node_columns, format);
  check_same_columns(m.cell_columns, u.cell_columns, format);
}

}  // namespace tear::fuzz

// Optional: seed inputs a target makes itself (a checkpoint in this build's format), replayed
// with the corpus and written as files by `replay_NAME --write-seeds DIR`.
extern "C" {
typedef void (*TearFuzzEmit)(const char* name, const uint8_t* data, size_t size);
__attribute__((weak)) void TearFuzzSeeds(TearFuzzEmit emit);
}
