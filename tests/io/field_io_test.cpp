// Frame rows from particle ids (io/field_io.h).
#include "tear/io/field_io.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace tear {
namespace {

std::string rows_error(const std::vector<uint32_t>& id) {
  try {
    rows_by_id(id);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "no error";
}

// Found by fuzzing the checkpoint reader (tests/fuzz): decode_checkpoint takes the ids as the
// file has them, and rows_by_id wrote through an id past the end (heap corruption at the first
// frame written after resuming from a forged checkpoint).
TEST(FieldIo, RowsByIdRefusesIdsThatAreNoPermutation) {
  EXPECT_EQ(rows_by_id({2, 0, 1}), (std::vector<uint32_t>{1, 2, 0}));
  EXPECT_TRUE(rows_by_id({}).empty());
  EXPECT_EQ(rows_error({0, 7, 1}),
            "particle ids are not a permutation of 0..3 - 1: id 7 at row 1 is out of range");
  EXPECT_EQ(rows_error({1, 0, 1}),
            "particle ids are not a permutation of 0..3 - 1: id 1 at row 2 appears twice");
}

}  // namespace
}  // namespace tear
