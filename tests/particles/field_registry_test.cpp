// The field registry: a field declared once is resized, appended, permuted, erased, written to
// frame tables and checkpoints, migrated and counted in memory figures without any other code
// naming it.
#include "tear/io/field_io.h"
#include "tear/io/frames.h"
#include "tear/io/ply.h"
#include "tear/particles/particles.h"
#include "tear/particles/records.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>

namespace tear {
namespace {

// A store with fields that no other code knows: one state field written to frames, one
// optional state field, one scratch field.
struct TestStore : Particles<2> {
  Field<Real> test_only{this, state_field("test_only", {{"test_only"}, ColumnType::Float32}), 7};
  Field<int32_t> sometimes{this, optional_state_field("sometimes"), -3};
  Field<Vec<2>> temp{this, scratch_field("temp"), Vec<2>(1, 2)};
};

TestStore store_of(size_t n) {
  TestStore s;
  for (size_t i = 0; i < n; ++i)
    s.push_back(Vec<2>(Real(i), Real(2 * i)), Vec<2>(Real(i), 0), Mat<2>::Identity(), 1, 1,
                uint16_t(i % 3));
  for (size_t i = 0; i < n; ++i) s.test_only[i] = Real(100 + i);
  return s;
}

TEST(FieldRegistry, ADeclaredFieldIsSizedWithTheStoreAtItsDefault) {
  TestStore s = store_of(4);
  EXPECT_EQ(s.size(), 4u);
  EXPECT_EQ(s.test_only.size(), 4u);
  EXPECT_EQ(s.temp.size(), 4u);
  EXPECT_EQ(s.temp[3], Vec<2>(1, 2));
  EXPECT_TRUE(s.sometimes.empty());  // optional, not enabled
  s.resize(6);
  EXPECT_EQ(s.test_only[5], 7);
  EXPECT_EQ(s.F[5], Mat<2>::Identity());
  EXPECT_EQ(s.reorder_slot[5], -1);
  s.enable("sometimes");
  ASSERT_EQ(s.sometimes.size(), 6u);
  EXPECT_EQ(s.sometimes[0], -3);
  EXPECT_THROW(s.enable("test_only"), std::invalid_argument);
  EXPECT_THROW(s.enable("nope"), std::invalid_argument);
}

TEST(FieldRegistry, PermuteMovesStateFieldsAndLeavesScratch) {
  TestStore s = store_of(5);
  s.enable("sometimes");
  for (size_t i = 0; i < 5; ++i) s.sometimes[i] = int32_t(10 * i), s.temp[i] = Vec<2>(Real(i), 0);
  const std::vector<uint32_t> order = {3, 0, 4, 1, 2};
  s.permute(order);
  for (size_t k = 0; k < 5; ++k) {
    EXPECT_EQ(s.id[k], order[k]);
    EXPECT_EQ(s.test_only[k], Real(100 + order[k]));
    EXPECT_EQ(s.sometimes[k], int32_t(10 * order[k]));
    EXPECT_EQ(s.temp[k][0], Real(k));  // scratch: recomputed before use, not moved
  }
}

// A reorder swaps each field with a spare of its type (FieldRegistry::spare): reorders in a
// row, and a copy's reorders, must each see their own values.
TEST(FieldRegistry, ReordersInARowAndCopiesKeepTheirOwnValues) {
  TestStore s = store_of(6);
  s.permute({5, 4, 3, 2, 1, 0});
  TestStore copy = s;
  s.permute({1, 0, 3, 2, 5, 4});
  copy.permute({0, 2, 4, 1, 3, 5});
  const std::vector<uint32_t> ids = {4, 5, 2, 3, 0, 1}, copy_ids = {5, 3, 1, 4, 2, 0};
  for (size_t k = 0; k < 6; ++k) {
    EXPECT_EQ(s.id[k], ids[k]);
    EXPECT_EQ(s.test_only[k], Real(100 + ids[k]));
    EXPECT_EQ(s.x[k][1], Real(2 * ids[k]));
    EXPECT_EQ(s.material[k], uint16_t(ids[k] % 3));
    EXPECT_EQ(copy.id[k], copy_ids[k]);
    EXPECT_EQ(copy.test_only[k], Real(100 + copy_ids[k]));
    EXPECT_EQ(copy.x[k][0], Real(copy_ids[k]));
  }
}

TEST(FieldRegistry, MemoryFigureCountsEveryEnabledField) {
  TestStore s = store_of(3);
  Particles<2> plain;
  const size_t extra = sizeof(Real) + sizeof(Vec<2>);  // test_only + temp
  EXPECT_EQ(s.bytes_per_particle(), plain.bytes_per_particle() + extra);
  s.enable("sometimes");
  EXPECT_EQ(s.bytes_per_particle(), plain.bytes_per_particle() + extra + sizeof(int32_t));
}

TEST(FieldRegistry, CopiesListTheirOwnFields) {
  TestStore a = store_of(3);
  TestStore b = a;  // the registry's entries must point into b, not a
  b.test_only[1] = 42;
  b.resize(4);
  EXPECT_EQ(a.test_only[1], Real(101));
  EXPECT_EQ(a.size(), 3u);
  EXPECT_EQ(b.test_only.size(), 4u);
  TestStore c = std::move(b);
  c.resize(5);
  EXPECT_EQ(c.test_only[1], 42);
  EXPECT_EQ(c.test_only[4], 7);
}

TEST(FieldRegistry, FrameTableHasTheDeclaredColumnsInIdOrder) {
  TestStore s = store_of(4);
  s.permute({2, 3, 0, 1});
  const PointTable t = frame_table(s, rows_by_id(s.id));
  const std::vector<std::string> names = {"id",     "x",        "y",  "z",  "vx", "vy",       "vz",
                                          "damage", "material", "fx", "fy", "fz", "test_only"};
  EXPECT_EQ(t.names, names);
  for (size_t k = 0; k < 4; ++k) {
    EXPECT_EQ(t.column("id")[k], double(k));
    EXPECT_EQ(t.column("y")[k], double(2 * k));
    EXPECT_EQ(t.column("z")[k], 0.0);
    EXPECT_EQ(t.column("test_only")[k], double(100 + k));
    EXPECT_EQ(t.column("fx")[k], 1.0);
  }
  EXPECT_EQ(t.types[0], ColumnType::Int32);
  EXPECT_EQ(t.types[8], ColumnType::UInt8);
}

// A frame streamed from the store a chunk of rows at a time (what a run writes) is the file of
// its whole table, byte for byte: across chunk boundaries (4096 rows), with reordered particles,
// an enabled optional column, and a buffer kept from a larger and from a smaller frame.
TEST(FieldRegistry, StreamedFrameEqualsTheFrameOfItsTable) {
  std::string kept = "left over from an earlier, larger frame" + std::string(400000, 'x');
  for (const size_t n : {size_t(0), size_t(1), size_t(4095), size_t(4097), size_t(10000)}) {
    TestStore s = store_of(n);
    s.enable("damage_laplacian");
    for (size_t i = 0; i < n; ++i)
      s.F[i](0, 1) = Real(0.001) * Real(i % 17), s.damage_laplacian[i] = Real(i) / 3;
    std::vector<uint32_t> order(n);
    for (size_t k = 0; k < n; ++k) order[k] = uint32_t((k * 7919) % n);  // 7919 is prime
    s.permute(order);
    const std::vector<uint32_t> rows = rows_by_id(s.id);
    const PointTable t = frame_table(s, rows);
    const std::string whole = encode_ply(t);
    encode_ply(frame_rows(s, rows), &kept);
    EXPECT_EQ(kept, whole) << n << " particles";
    std::string fresh;
    encode_points(frame_rows(s, rows), "ply", &fresh);
    EXPECT_EQ(fresh, whole) << n << " particles";
    // The column formats take the whole table first: the same file as from the table.
    for (const char* format : {"bgeo", "vtu"}) {
      PointTable scratch;
      encode_points(frame_rows(s, rows), format, &fresh, &scratch);
      EXPECT_EQ(fresh, encode_points(t, format)) << format << ", " << n << " particles";
    }
    EXPECT_THROW(encode_points(frame_rows(s, rows), "xyz", &fresh), std::runtime_error);
  }
}

// The optional frame columns a scene may ask for (output.fields) are listed, absent until
// enabled, and then written from their fields: driving_force from the damage update's `drive`
// (0 where damage is not simulated), damage_laplacian from its own field (plastic_strain and
// fiber_tension, which plastic and inextensible materials enable, are listed too).
TEST(FieldRegistry, OptionalColumnsAreWrittenOnlyWhereEnabled) {
  TestStore s = store_of(3);
  EXPECT_EQ(s.optional_columns(),
            (std::vector<std::string>{"plastic_strain", "fiber_tension", "driving_force",
                                      "damage_laplacian", "contact", "normal_stretch"}));
  // A scene may ask for the solids' ones; an element group has the last two on already.
  EXPECT_EQ(s.requestable_columns(),
            (std::vector<std::string>{"plastic_strain", "fiber_tension", "driving_force",
                                      "damage_laplacian"}));
  const std::vector<std::string> plain = frame_table(s, rows_by_id(s.id)).names;
  EXPECT_EQ(plain.back(), "test_only");
  EXPECT_EQ(std::count(plain.begin(), plain.end(), "driving_force"), 0);
  s.enable("driving_force");
  s.enable("damage_laplacian");
  EXPECT_EQ(s.damage_laplacian.size(), 3u);
  std::vector<std::string> names = plain;
  names.insert(names.end() - 1, {"driving_force", "damage_laplacian"});
  PointTable t = frame_table(s, rows_by_id(s.id));
  EXPECT_EQ(t.names, names);
  EXPECT_EQ(t.column("driving_force"), std::vector<double>(3, 0.0));  // no `drive` here
  s.enable("drive");
  for (size_t i = 0; i < 3; ++i) s.drive[i] = Real(1.5 * i), s.damage_laplacian[i] = -Real(i);
  s.permute({2, 0, 1});
  t = frame_table(s, rows_by_id(s.id));
  EXPECT_EQ(t.column("driving_force"), (std::vector<double>{0, 1.5, 3}));
  EXPECT_EQ(t.column("damage_laplacian"), (std::vector<double>{0, -1, -2}));
  // A copy of the store writes the same columns.
  TestStore copy;
  copy.enable_like(s);
  copy.resize(3);
  EXPECT_EQ(frame_table(copy, {0, 1, 2}).names, names);  // resized: its ids are all 0
}

TEST(FieldRegistry, CheckpointRecordsRoundTripEveryStateField) {
  TestStore s = store_of(5);
  s.enable("sometimes");
  for (size_t i = 0; i < 5; ++i) s.sometimes[i] = int32_t(i * i), s.F[i](0, 1) = Real(i);
  ByteWriter w;
  put_fields(s, &w);
  TestStore back;
  back.enable_like(s);
  const std::string bytes = w.bytes();
  ByteReader r(bytes);
  get_fields(&r, 5, &back);
  EXPECT_TRUE(r.at_end());
  ASSERT_EQ(back.size(), 5u);
  EXPECT_EQ(back.temp.size(), 5u);  // scratch sized, not read
  for (size_t i = 0; i < 5; ++i) {
    EXPECT_EQ(back.test_only[i], s.test_only[i]);
    EXPECT_EQ(back.sometimes[i], int32_t(i * i));
    EXPECT_EQ(back.F[i], s.F[i]);
    EXPECT_EQ(back.x[i], s.x[i]);
  }
}

// A field with one value for every particle is written once (mass, vol0, F and C of this store;
// x, v and test_only vary), and read back as that value for every particle. compact = false
// writes every value; the version A layout (no flag byte) is still read.
TEST(FieldRegistry, CheckpointWritesAFieldOfOneValueOnce) {
  constexpr size_t n = 6;
  TestStore s = store_of(n);
  ByteWriter compact, full;
  put_fields(s, &compact);
  put_fields(s, &full, false);
  size_t once = 0;  // bytes of the fields with one value, less one element each
  for (const FieldRegistry::Entry& e : s.entries()) {
    if (e.info().role != FieldRole::State || !s.stored(e)) continue;
    const char* d = s.field_data(e);
    bool uniform = true;
    for (size_t i = 1; i < n; ++i)
      uniform = uniform && std::equal(d, d + e.element_bytes(), d + i * e.element_bytes());
    if (uniform) once += (n - 1) * e.element_bytes();
  }
  EXPECT_GE(once, (n - 1) * (2 * sizeof(Real) + 2 * sizeof(Mat<2>)));
  EXPECT_EQ(compact.size() + once, full.size());
  // Version A: the same records without the flag byte.
  ByteWriter version_a;
  uint32_t count = 0;
  for (const FieldRegistry::Entry& e : s.entries())
    count += e.info().role == FieldRole::State && s.stored(e);
  version_a.put<uint32_t>(count);
  for (const FieldRegistry::Entry& e : s.entries()) {
    if (e.info().role != FieldRole::State || !s.stored(e)) continue;
    version_a.put<uint32_t>(uint32_t(e.info().name.size()));
    version_a.put_bytes(e.info().name);
    version_a.put<uint32_t>(uint32_t(e.element_bytes()));
    version_a.put<uint64_t>(n);
    version_a.put_bytes(s.field_data(e), n * e.element_bytes());
  }
  for (const auto& [writer, flags] : {std::pair<const ByteWriter*, bool>{&compact, true},
                                      {&full, true},
                                      {&version_a, false}}) {
    TestStore back;
    const std::string bytes = writer->bytes();
    ByteReader r(bytes);
    get_fields(&r, n, &back, flags);
    EXPECT_TRUE(r.at_end());
    ASSERT_EQ(back.size(), n);
    for (size_t i = 0; i < n; ++i) {
      EXPECT_EQ(back.x[i], s.x[i]);
      EXPECT_EQ(back.test_only[i], s.test_only[i]);
      EXPECT_EQ(back.mass[i], s.mass[i]);
      EXPECT_EQ(back.F[i], s.F[i]);
      EXPECT_EQ(back.material[i], s.material[i]);
    }
  }
  // A flag byte other than 0 and 1 is refused.
  std::string bad = compact.bytes();
  const size_t flag = 4 + 4 + 2 + 4 + 8;  // count, then the first field ("id"): name, size, n
  ASSERT_EQ(bad[flag], 0);  // ids differ
  bad[flag] = 2;
  TestStore back;
  ByteReader r(bad);
  EXPECT_THROW(get_fields(&r, n, &back), std::runtime_error);
}

TEST(FieldRegistry, CheckpointOfOtherFieldsIsRefusedByName) {
  TestStore s = store_of(2);
  s.enable("sometimes");
  s.sometimes[1] = 5;  // not the default (-3) everywhere: a store with it off cannot skip it
  ByteWriter writer;
  put_fields(s, &writer);
  const std::string bytes = writer.bytes();
  auto error_of = [](const std::string& bytes, size_t n, TestStore* store) {
    ByteReader r(bytes);
    try {
      get_fields(&r, n, store);
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  TestStore without;  // "sometimes" not enabled: the checkpoint has one field more
  EXPECT_NE(error_of(bytes, 2, &without).find("more than"), std::string::npos);
  // A store that declares a field the checkpoint lacks names it.
  ByteWriter w_without;
  put_fields(without = store_of(2), &w_without);
  TestStore with;
  with.enable("sometimes");
  const std::string missing = error_of(w_without.bytes(), 2, &with);
  EXPECT_NE(missing.find("corrupt checkpoint"), std::string::npos) << missing;
  EXPECT_NE(missing.find("\"sometimes\""), std::string::npos) << missing;
  TestStore other;
  other.enable("sometimes");
  ByteReader r2(bytes);
  EXPECT_THROW(get_fields(&r2, 3, &other), std::runtime_error);  // wrong particle count
  const std::string cut = bytes.substr(0, bytes.size() - 1);
  ByteReader r3(cut);
  EXPECT_THROW(get_fields(&r3, 2, &other), std::runtime_error);  // truncated
}

// A checkpoint field that the store has off is skipped where it holds nothing but the field's
// default (what off means; a tear before 2026-12 wrote the fiber frame of every body), in the
// compact and the full layout, and refused where one value differs.
TEST(FieldRegistry, CheckpointFieldOfDefaultsThatTheStoreHasOffIsSkipped) {
  for (const bool compact : {true, false}) {
    SCOPED_TRACE(compact ? "compact" : "full");
    TestStore s = store_of(3);
    s.enable("sometimes");  // every value the default, -3
    ASSERT_TRUE(s.enabled("fiber"));
    for (size_t i = 0; i < 3; ++i) s.F[i](1, 0) = Real(i);
    ByteWriter w;
    put_fields(s, &w, compact);
    const std::string bytes = w.bytes();
    TestStore back;
    ASSERT_TRUE(back.drop_identity_fibers());  // empty: every frame the identity
    ByteReader r(bytes);
    get_fields(&r, 3, &back, true);
    EXPECT_TRUE(r.at_end());
    EXPECT_FALSE(back.enabled("fiber"));
    EXPECT_FALSE(back.enabled("sometimes"));
    ASSERT_EQ(back.size(), 3u);
    for (size_t i = 0; i < 3; ++i) {
      EXPECT_EQ(back.F[i], s.F[i]);
      EXPECT_EQ(back.fiber_of(i), Mat<2>::Identity());
      EXPECT_EQ(back.test_only[i], s.test_only[i]);
    }
    // One frame turned: the field is not all defaults, and the store without it refuses it.
    s.fiber[2] << 0, -1, 1, 0;
    ByteWriter turned;
    put_fields(s, &turned, compact);
    const std::string turned_bytes = turned.bytes();
    TestStore off;
    off.drop_identity_fibers();
    ByteReader r2(turned_bytes);
    try {
      get_fields(&r2, 3, &off, true);
      ADD_FAILURE() << "a turned fiber frame was dropped";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("\"fiber\" where \"mass\" was expected"),
                std::string::npos)
          << e.what();
    }
  }
}

// Disable releases a field's storage; enable_like turns fields on and off as the other store has
// them.
TEST(FieldRegistry, DisableReleasesAndEnableLikeMatchesBothWays) {
  TestStore s = store_of(4);
  s.enable("sometimes");
  EXPECT_EQ(s.sometimes.size(), 4u);
  s.disable("sometimes");
  EXPECT_FALSE(s.enabled("sometimes"));
  EXPECT_EQ(s.sometimes.capacity(), 0u);
  EXPECT_THROW(s.disable("test_only"), std::invalid_argument);
  EXPECT_THROW(s.disable("nope"), std::invalid_argument);
  const size_t with_fiber = s.bytes_per_particle();
  s.disable("fiber");
  EXPECT_EQ(s.bytes_per_particle(), with_fiber - sizeof(Mat<2>));
  TestStore other = store_of(4);
  other.enable("sometimes");
  other.enable_like(s);  // fiber and sometimes off
  EXPECT_FALSE(other.enabled("fiber"));
  EXPECT_FALSE(other.enabled("sometimes"));
  s.enable("sometimes");
  other.enable_like(s);
  EXPECT_TRUE(other.enabled("sometimes"));
  EXPECT_EQ(other.sometimes.size(), 4u);
}

TEST(FieldRegistry, MigrationRecordsRoundTrip) {
  TestStore s = store_of(6);
  RegistryRecords records(&s, "x");
  double pos[3];
  records.position(4, pos);
  EXPECT_EQ(pos[0], 4.0);
  EXPECT_EQ(pos[1], 8.0);
  EXPECT_EQ(pos[2], 0.0);
  std::string packed;
  records.pack({1, 4}, &packed);
  EXPECT_EQ(packed.size(), 2 * records.record_bytes());
  records.erase({1, 4});
  ASSERT_EQ(s.size(), 4u);
  EXPECT_EQ(s.id[1], 2u);
  records.append(packed);
  ASSERT_EQ(s.size(), 6u);
  EXPECT_EQ(s.id[4], 1u);
  EXPECT_EQ(s.id[5], 4u);
  EXPECT_EQ(s.test_only[5], Real(104));
  EXPECT_EQ(s.temp.size(), 6u);
}

}  // namespace
}  // namespace tear
