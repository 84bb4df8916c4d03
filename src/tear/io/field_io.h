// io/: particle stores as frame tables and as checkpoint records, both from the field registry
// (particles/field.h): a field declared in a store is written and read back without any code
// here naming it.
#pragma once

#include "tear/io/binary.h"
#include "tear/io/point_table.h"
#include "tear/particles/field.h"

#include <cstdint>
#include <vector>

namespace tear {

// The frame columns of every enabled field (and derived columns) of `store`, in declaration
// order; row k is particle rows[k]. The rows refer to `store` and `rows`, which must outlive
// them and not change meanwhile.
PointRows frame_rows(const FieldRegistry& store, const std::vector<uint32_t>& rows);
// The same as a table.
PointTable frame_table(const FieldRegistry& store, const std::vector<uint32_t>& rows);

// rows[k] = the index of the particle whose id is k: frame rows in id order, so frames compare
// row by row across frames and runs. Throws std::runtime_error unless the ids are a permutation
// of 0..n-1 (a damaged or forged checkpoint can hold any ids).
std::vector<uint32_t> rows_by_id(const std::vector<uint32_t>& id);

// The state fields of `store` (enabled ones, declaration order): for each its name, element
// size, count, a byte that is 1 where every particle holds the same value, and the bytes (that
// one value, or all; referenced in place: `store` must not change until `w` is used).
// compact false: every value of every field (the largest size the fields can take).
void put_fields(const FieldRegistry& store, ByteWriter* w, bool compact = true);
// Reads what put_fields wrote into `store`'s state fields (`uniform_flags` false: a layout
// without the byte, every value written, as checkpoint format A had). Throws
// std::runtime_error("corrupt checkpoint (...)") naming the field when the names, element
// sizes or counts differ from the store's declarations or from `count` particles.
void get_fields(ByteReader* r, size_t count, FieldRegistry* store, bool uniform_flags = true);

}  // namespace tear
