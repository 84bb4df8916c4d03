#include "tear/io/field_io.h"

#include "tear/exec/parallel.h"

#include <stdexcept>
#include <string>

namespace tear {

PointTable frame_table(const FieldRegistry& store, const std::vector<uint32_t>& rows) {
  PointTable t;
  t.count = rows.size();
  for (const FieldRegistry::Entry& e : store.entries()) {
    const FieldColumns& c = e.info().columns;
    if (c.names.empty() || !store.enabled(e)) continue;
    const size_t n = c.names.size();
    std::vector<std::vector<double>> values(n, std::vector<double>(rows.size()));
    parallel_for(rows.size(), [&](size_t k) {
      double row[8];
      store.columns(e, rows[k], row);
      for (size_t j = 0; j < n; ++j) values[j][k] = row[j];
    });
    for (size_t j = 0; j < n; ++j) t.add(c.names[j], c.type, std::move(values[j]));
  }
  return t;
}

std::vector<uint32_t> rows_by_id(const std::vector<uint32_t>& id) {
  std::vector<uint32_t> row(id.size());
  for (size_t i = 0; i < id.size(); ++i) row[id[i]] = uint32_t(i);
  return row;
}

void put_fields(const FieldRegistry& store, ByteWriter* w) {
  uint32_t count = 0;
  for (const FieldRegistry::Entry& e : store.entries())
    if (e.info().role == FieldRole::State && store.stored(e)) ++count;
  w->put<uint32_t>(count);
  for (const FieldRegistry::Entry& e : store.entries()) {
    if (e.info().role != FieldRole::State || !store.stored(e)) continue;
    const std::string& name = e.info().name;
    w->put<uint32_t>(uint32_t(name.size()));
    w->bytes().append(name);
    w->put<uint32_t>(uint32_t(e.element_bytes()));
    const size_t n = store.field_size(e);
    w->put<uint64_t>(n);
    w->bytes().append(store.field_data(e), n * e.element_bytes());
  }
}

void get_fields(ByteReader* r, size_t count, FieldRegistry* store) {
  auto corrupt = [](const std::string& why) {
    return std::runtime_error("corrupt checkpoint (" + why + ")");
  };
  std::vector<const FieldRegistry::Entry*> expected;
  for (const FieldRegistry::Entry& e : store->entries())
    if (e.info().role == FieldRole::State && store->stored(e)) expected.push_back(&e);
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
    store->assign_field(*e, r->get_view(size_t(n) * e->element_bytes()), size_t(n));
  }
  if (fields > expected.size())
    throw corrupt(std::to_string(fields - expected.size()) +
                  " particle field(s) more than the scene's particles have");
  store->resize(count);  // the scratch fields
}

}  // namespace tear
