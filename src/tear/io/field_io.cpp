#include "tear/io/field_io.h"

#include "tear/exec/memory.h"
#include "tear/exec/parallel.h"

#include <cstring>
#include <stdexcept>
#include <string>

namespace tear {

PointTable frame_table(const FieldRegistry& store, const std::vector<uint32_t>& rows) {
  PointTable t;
  fill_frame_table(store, rows, &t);
  return t;
}

void fill_frame_table(const FieldRegistry& store, const std::vector<uint32_t>& rows,
                      PointTable* table) {
  // The columns, in order: (entry, its column k).
  std::vector<std::pair<const FieldRegistry::Entry*, size_t>> columns;
  std::vector<std::string> names;
  std::vector<ColumnType> types;
  for (const FieldRegistry::Entry& e : store.entries()) {
    const FieldColumns& c = e.info().columns;
    if (c.names.empty() || !store.enabled(e)) continue;
    for (size_t k = 0; k < c.names.size(); ++k) {
      columns.emplace_back(&e, k);
      names.push_back(c.names[k]);
      types.push_back(c.type);
    }
  }
  PointTable& t = *table;
  if (t.names != names || t.types != types) {
    t = PointTable();
    t.names = names;
    t.types = types;
    t.columns.resize(names.size());
  }
  t.count = rows.size();
  for (std::vector<double>& c : t.columns) reserve_large(&c, rows.size()), c.resize(rows.size());
  // In chunks of rows, every field's columns for a chunk (its fields read once, in cache).
  constexpr size_t kChunk = 4096;
  parallel_for((rows.size() + kChunk - 1) / kChunk, [&](size_t chunk) {
    const size_t begin = chunk * kChunk, count = std::min(rows.size(), begin + kChunk) - begin;
    double* out[8];
    for (size_t j = 0; j < columns.size();) {
      const FieldRegistry::Entry& e = *columns[j].first;
      const size_t n = e.info().columns.names.size();
      for (size_t c = 0; c < n; ++c) out[c] = t.columns[j + c].data() + begin;
      store.columns(e, rows.data() + begin, count, out);
      j += n;
    }
  });
}

namespace {

// Whether a checkpoint holds field `e` of `store`: state (not scratch) with values here.
bool checkpointed(const FieldRegistry& store, const FieldRegistry::Entry& e) {
  return e.info().role == FieldRole::State && store.stored(e);
}

}  // namespace

std::vector<uint32_t> rows_by_id(const std::vector<uint32_t>& id) {
  constexpr uint32_t kNone = UINT32_MAX;
  std::vector<uint32_t> row(id.size(), kNone);
  for (size_t i = 0; i < id.size(); ++i) {
    // Ids come from checkpoints too: checked, as writing through a bad one corrupts memory.
    if (id[i] >= id.size() || row[id[i]] != kNone)
      throw std::runtime_error("particle ids are not a permutation of 0.." +
                               std::to_string(id.size()) + " - 1: id " + std::to_string(id[i]) +
                               " at row " + std::to_string(i) +
                               (id[i] < id.size() ? " appears twice" : " is out of range"));
    row[id[i]] = uint32_t(i);
  }
  return row;
}

void put_fields(const FieldRegistry& store, ByteWriter* w, bool compact) {
  uint32_t count = 0;
  for (const FieldRegistry::Entry& e : store.entries())
    if (checkpointed(store, e)) ++count;
  w->put<uint32_t>(count);
  for (const FieldRegistry::Entry& e : store.entries()) {
    if (!checkpointed(store, e)) continue;
    const std::string& name = e.info().name;
    w->put<uint32_t>(uint32_t(name.size()));
    w->put_bytes(name);
    w->put<uint32_t>(uint32_t(e.element_bytes()));
    const size_t n = store.field_size(e), size = e.element_bytes();
    w->put<uint64_t>(n);
    // A field that holds one value for every particle (a material's mass, rest volume or fiber
    // frame, undamaged particles' damage) is written once.
    const char* data = store.field_data(e);
    auto differs = [&](size_t i) { return std::memcmp(data + i * size, data, size) != 0; };
    const bool uniform = compact && n > 1 && !parallel_any(n, differs);
    w->put<uint8_t>(uniform ? 1 : 0);
    w->put_view(data, uniform ? size : n * size);
  }
}

void get_fields(ByteReader* r, size_t count, FieldRegistry* store, bool uniform_flags) {
  auto corrupt = [](const std::string& why) {
    return std::runtime_error("corrupt checkpoint (" + why + ")");
  };
  std::vector<const FieldRegistry::Entry*> expected;
  for (const FieldRegistry::Entry& e : store->entries())
    if (checkpointed(*store, e)) expected.push_back(&e);
  const uint32_t fields = r->get<uint32_t>();
  for (size_t k = 0; k < expected.size(); ++k) {
    const FieldRegistry::Entry* e = expected[k];
    if (k == fields)
      throw corrupt("no particle field \"" + e->info().name + "\"; written by another version?");
    const uint32_t length = r->get<uint32_t>();
    if (length > 256) throw corrupt("field name too long");
    const std::string name(r->get_view(length), length);
    if (name != e->info().name)
      throw corrupt("particle field \"" + name + "\" where \"" + e->info().name +
                    "\" was expected; written by another version?");
    if (r->get<uint32_t>() != e->element_bytes())
      throw corrupt("particle field \"" + name + "\" has another element size");
    const uint64_t n = r->get<uint64_t>();
    if (n != count)
      throw corrupt("particle field \"" + name + "\" has " + std::to_string(n) + " values for " +
                    std::to_string(count) + " particles");
    const uint8_t uniform = uniform_flags ? r->get<uint8_t>() : 0;
    if (uniform > 1) throw corrupt("particle field \"" + name + "\" has a bad layout flag");
    if (uniform)
      store->fill_field(*e, r->get_view(e->element_bytes()), size_t(n));
    else
      store->assign_field(*e, r->get_view(size_t(n) * e->element_bytes()), size_t(n));
  }
  if (fields > expected.size())
    throw corrupt(std::to_string(fields - expected.size()) +
                  " particle field(s) more than the scene's particles have");
  store->resize(count);  // the scratch fields
}

}  // namespace tear
