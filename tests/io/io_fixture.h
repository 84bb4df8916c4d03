// Shared by the io tests: a table shaped like a simulation frame, what BGEO and VTU make of it,
// and the message that a decoder throws.
#pragma once

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "tear/io/point_table.h"

namespace tear {

// A table shaped like Simulation::frame_table() (z, vz, fz = 0 in 2D), values exact in float.
inline PointTable frame_like(int dim, size_t n) {
  PointTable t;
  t.count = n;
  auto col = [&](double scale, double offset, bool used) {
    std::vector<double> c(n);
    for (size_t i = 0; i < n; ++i) c[i] = used ? offset + scale * double(i) : 0.0;
    return c;
  };
  t.add("id", ColumnType::Int32, col(1, 0, true));
  t.add("x", ColumnType::Float32, col(0.25, 0.5, true));
  t.add("y", ColumnType::Float32, col(-0.125, 1, true));
  t.add("z", ColumnType::Float32, col(0.5, 0.75, dim == 3));
  t.add("vx", ColumnType::Float32, col(1.5, -2, true));
  t.add("vy", ColumnType::Float32, col(-0.75, 3, true));
  t.add("vz", ColumnType::Float32, col(2, 0.25, dim == 3));
  t.add("damage", ColumnType::Float32, col(0.0625, 0, true));
  t.add("material", ColumnType::UInt8, col(1, 0, true));
  t.add("fx", ColumnType::Float32, col(0, 1, true));
  t.add("fy", ColumnType::Float32, col(0.5, 0, true));
  t.add("fz", ColumnType::Float32, col(-0.5, 0, dim == 3));
  return t;
}

// A frame_like table after a BGEO or VTU round trip: in canonical order (position first, then
// the attributes in the table's order), integer columns as Int32 and the others as Float32.
inline void expect_canonical_frame_columns(const PointTable& d) {
  EXPECT_EQ(d.names, (std::vector<std::string>{"x", "y", "z", "id", "vx", "vy", "vz", "damage",
                                               "material", "fx", "fy", "fz"}));
  for (size_t c = 0; c < d.names.size(); ++c) {
    const bool integer = d.names[c] == "id" || d.names[c] == "material";
    EXPECT_EQ(d.types[c], integer ? ColumnType::Int32 : ColumnType::Float32) << d.names[c];
  }
}

// The message `decode` throws for `bytes`, or "no error".
template <class Decode>
std::string error_of(Decode decode, const std::string& bytes) {
  try {
    decode(bytes);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace tear
