#include "tear/particles/records.h"

#include <cstring>
#include <stdexcept>

namespace tear {

RegistryRecords::RegistryRecords(FieldRegistry* store, const std::string& position)
    : store_(store), position_(store->find(position)) {
  if (!position_) throw std::invalid_argument("no particle field \"" + position + "\"");
}

std::vector<const FieldRegistry::Entry*> RegistryRecords::state_fields() const {
  std::vector<const FieldRegistry::Entry*> out;
  for (const FieldRegistry::Entry& e : store_->entries())
    if (e.info().role == FieldRole::State && store_->stored(e)) out.push_back(&e);
  return out;
}

size_t RegistryRecords::record_bytes() const {
  size_t bytes = 0;
  for (const FieldRegistry::Entry* e : state_fields()) bytes += e->element_bytes();
  return bytes;
}

void RegistryRecords::position(size_t i, double out[3]) const {
  double c[3] = {0, 0, 0};
  store_->columns(*position_, i, c);
  for (int k = 0; k < 3; ++k) out[k] = k < position_->components() ? c[k] : 0.0;
}

void RegistryRecords::pack(const std::vector<uint32_t>& which, std::string* out) const {
  const std::vector<const FieldRegistry::Entry*> fields = state_fields();
  for (uint32_t i : which)
    for (const FieldRegistry::Entry* e : fields)
      out->append(store_->field_data(*e) + size_t(i) * e->element_bytes(), e->element_bytes());
}

void RegistryRecords::append(const std::string& records) {
  const std::vector<const FieldRegistry::Entry*> fields = state_fields();
  const size_t bytes = record_bytes();
  if (bytes == 0 || records.size() % bytes != 0)
    throw std::invalid_argument("particle records of the wrong size");
  const char* p = records.data();
  for (size_t r = 0; r < records.size() / bytes; ++r) {
    const size_t i = store_->append();
    for (const FieldRegistry::Entry* e : fields) {
      std::memcpy(store_->element(*e, i), p, e->element_bytes());
      p += e->element_bytes();
    }
  }
}

}  // namespace tear
