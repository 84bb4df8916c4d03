// particles/: a particle store seen as records of bytes (exec/domain.h's ParticleRecords), made
// from the field registry: what a multi-process run migrates between ranks. A record holds the
// particle's state fields in declaration order; scratch fields are recomputed after arrival.
#pragma once

#include "tear/exec/domain.h"
#include "tear/particles/field.h"

#include <string>
#include <vector>

namespace tear {

class RegistryRecords final : public ParticleRecords {
 public:
  // `position`: the name of the store's position field (a Vec of Real).
  RegistryRecords(FieldRegistry* store, const std::string& position);

  size_t size() const override { return store_->size(); }
  void position(size_t i, double out[3]) const override;
  void pack(const std::vector<uint32_t>& which, std::string* out) const override;
  void erase(const std::vector<uint32_t>& which) override { store_->erase(which); }
  void append(const std::string& records) override;
  // Bytes of one record.
  size_t record_bytes() const;

 private:
  std::vector<const FieldRegistry::Entry*> state_fields() const;
  FieldRegistry* store_;
  const FieldRegistry::Entry* position_;
};

}  // namespace tear
