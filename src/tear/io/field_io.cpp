#include "tear/io/field_io.h"

#include "tear/exec/memory.h"
#include "tear/exec/parallel.h"

#include <cstring>
#include <stdexcept>
#include <string>

namespace tear {

PointRows frame_rows(const FieldRegistry& store, const std::vector<uint32_t>& rows) {
  // The columns, in order: each entry with columns, then its column count.
  std::vector<const FieldRegistry::Entry*> entries;
  PointRows r;
  r.count = rows.size();
  for (const FieldRegistry::Entry& e : store.entries()) {
    const FieldColumns& c = e.info().columns;
    if (c.names.empty() || !store.enabled(e)) continue;
    entries.push_back(&e);
    for (const std::string& name : c.names) r.names.push_back(name), r.types.push_back(c.type);
  }
  // A chunk of rows: every field's columns for it (its fields read once, in cache).
  r.fill = [&store, &rows, entries](size_t begin, size_t n, double* const* out) {
    for (const FieldRegistry::Entry* e : entries) {
      store.columns(*e, rows.data() + begin, n, out);
      out += e->info().columns.names.size();
    }
  };
  return r;
}

PointTable frame_table(const FieldRegistry& store, const std::vector<uint32_t>& rows) {
  PointTable t;
  fill_table(frame_rows(store, rows), &t);
  return t;
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
  size_t k = 0;  // expected[k] is the next field the store has
  for (uint32_t j = 0; j < fields; ++j) {
    const uint32_t length = r->get<uint32_t>();
    if (length > 256) throw corrupt("field name too long");
    const std::string name(r->get_view(length), length);
    const FieldRegistry::Entry* next = k < expected.size() ? expected[k] : nullptr;
    // Not the next field: one that this store has off can still be skipped where every value
    // is the field's default (off means that: a tear before 2026-12 wrote the fiber frame of
    // every body, the identity where it is now off).
    const FieldRegistry::Entry* e = next && name == next->info().name ? next : store->find(name);
    const bool off = e != next && e && e->info().optional && e->info().role == FieldRole::State &&
                     !store->enabled(*e);
    auto refuse = [&] {
      if (!next)
        return corrupt(std::to_string(fields - j) +
                       " particle field(s) more than the scene's particles have");
      return corrupt("particle field \"" + name + "\" where \"" + next->info().name +
                     "\" was expected; written by another version?");
    };
    if (e != next && !off) throw refuse();
    if (r->get<uint32_t>() != e->element_bytes())
      throw corrupt("particle field \"" + name + "\" has another element size");
    const uint64_t n = r->get<uint64_t>();
    if (n != count)
      throw corrupt("particle field \"" + name + "\" has " + std::to_string(n) + " values for " +
                    std::to_string(count) + " particles");
    const uint8_t uniform = uniform_flags ? r->get<uint8_t>() : 0;
    if (uniform > 1) throw corrupt("particle field \"" + name + "\" has a bad layout flag");
    const size_t values = uniform ? 1 : size_t(n);
    const char* data = r->get_view(values * e->element_bytes());
    if (off) {
      const std::string& def = e->default_bytes();
      for (size_t i = 0; i < values; ++i)
        if (std::memcmp(data + i * def.size(), def.data(), def.size()) != 0) throw refuse();
      continue;
    }
    ++k;
    if (uniform)
      store->fill_field(*e, data, size_t(n));
    else
      store->assign_field(*e, data, size_t(n));
  }
  if (k < expected.size())
    throw corrupt("no particle field \"" + expected[k]->info().name +
                  "\"; written by another version?");
  store->resize(count);  // the scratch fields
}

}  // namespace tear
