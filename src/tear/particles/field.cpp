#include "tear/particles/field.h"

#include <stdexcept>

namespace tear {

size_t FieldRegistry::size() const {
  for (const Entry& e : entries_)
    if (!e.info_.optional && !e.derived()) return field_size(e);
  return 0;
}

void FieldRegistry::add_derived(FieldColumns columns,
                                void (*value)(const FieldRegistry&, size_t, double*),
                                bool optional) {
  Entry e;
  e.info_.name = columns.names.empty() ? std::string() : columns.names[0];
  e.info_.role = FieldRole::Scratch;
  e.info_.optional = optional;
  e.info_.columns = std::move(columns);
  e.derived_ = value;
  entries_.push_back(std::move(e));
  enabled_.push_back(0);
}

void FieldRegistry::columns(const Entry& e, size_t i, double* out) const {
  double* column[8];
  const size_t n = e.info_.columns.names.size();
  TEAR_ASSERT(n <= 8);
  for (size_t c = 0; c < n; ++c) column[c] = out + c;
  const uint32_t row = uint32_t(i);
  columns(e, &row, 1, column);
}

void FieldRegistry::columns(const Entry& e, const uint32_t* rows, size_t count,
                            double* const* out) const {
  const int n = int(e.info_.columns.names.size());
  if (!e.derived_) return e.columns_(at(e), rows, count, n, out);
  double row[8];
  TEAR_ASSERT(n <= 8);
  for (size_t k = 0; k < count; ++k) {
    e.derived_(*this, rows[k], row);
    for (int c = 0; c < n; ++c) out[c][k] = row[c];
  }
}

void FieldRegistry::resize(size_t n) {
  for (const Entry& e : entries_)
    if (stored(e)) e.resize_(at(e), n, e.default_.data());
}

void FieldRegistry::reserve(size_t n) {
  for (const Entry& e : entries_)
    if (stored(e)) e.reserve_(at(e), n);
}

size_t FieldRegistry::append() {
  const size_t i = size();
  resize(i + 1);
  return i;
}

void FieldRegistry::permute(const std::vector<uint32_t>& order) {
  TEAR_ASSERT(order.size() == size());
  for (const Entry& e : entries_)
    if (e.info_.role == FieldRole::State && stored(e)) e.permute_(at(e), order, this);
}

void FieldRegistry::erase(const std::vector<uint32_t>& which) {
  for (const Entry& e : entries_)
    if (stored(e)) e.erase_(at(e), which);
}

const FieldRegistry::Entry* FieldRegistry::find(const std::string& name) const {
  for (const Entry& e : entries_)
    if (e.info_.name == name) return &e;
  return nullptr;
}

const FieldRegistry::Entry& FieldRegistry::optional_entry(const std::string& name) const {
  const Entry* e = find(name);
  if (!e) throw std::invalid_argument("no particle field \"" + name + "\"");
  if (!e->info_.optional)
    throw std::invalid_argument("particle field \"" + name + "\" is not optional");
  return *e;
}

void FieldRegistry::enable(const std::string& name) {
  const Entry& e = optional_entry(name);
  const size_t k = index_of(e);
  if (enabled_[k]) return;
  enabled_[k] = 1;
  if (!e.derived()) e.resize_(at(e), size(), e.default_.data());
}

void FieldRegistry::disable(const std::string& name) {
  const Entry& e = optional_entry(name);
  enabled_[index_of(e)] = 0;
  if (!e.derived()) e.release_(at(e));
}

std::vector<std::string> FieldRegistry::optional_columns() const {
  std::vector<std::string> names;
  for (const Entry& e : entries_)
    if (e.info_.optional && !e.info_.columns.names.empty()) names.push_back(e.info_.name);
  return names;
}

void FieldRegistry::enable_like(const FieldRegistry& other) {
  TEAR_ASSERT(other.entries_.size() == entries_.size());
  for (size_t k = 0; k < entries_.size(); ++k) {
    if (!entries_[k].info_.optional) continue;
    if (other.enabled_[k])
      enable(entries_[k].info_.name);
    else
      disable(entries_[k].info_.name);
  }
}

bool FieldRegistry::stored(const Entry& e) const { return !e.derived() && enabled(e); }

bool FieldRegistry::enabled(const std::string& name) const {
  const Entry* e = find(name);
  return e && enabled(*e);
}

void FieldRegistry::assign_field(const Entry& e, const char* bytes, size_t count) {
  e.resize_(at(e), count, e.default_.data());
  if (count) std::memcpy(e.data_(at(e)), bytes, count * e.element_bytes_);
}

void FieldRegistry::fill_field(const Entry& e, const char* element, size_t count) {
  e.resize_(at(e), 0, element);
  e.resize_(at(e), count, element);
}

size_t FieldRegistry::bytes_per_particle() const {
  size_t bytes = 0;
  for (const Entry& e : entries_)
    if (stored(e)) bytes += e.element_bytes_;
  return bytes;
}

size_t FieldRegistry::memory_bytes() const {
  size_t bytes = 0;
  for (const Spares::Spare& s : spares_.list) bytes += s.bytes(s.vector.get());
  for (const Entry& e : entries_)
    if (stored(e)) bytes += e.capacity_(at(e)) * e.element_bytes_;
  return bytes;
}

}  // namespace tear
