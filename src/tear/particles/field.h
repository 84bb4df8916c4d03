// particles/: the per-particle field registry. A field is declared once, as a member of a
// particle store (`Field<T> x{this, {...}}`), and every operation over all fields -- resize,
// append, permute, erase, checkpoint records, frame columns, memory figures -- follows from that
// declaration. Knows nothing of grids, materials, files or scenes.
#pragma once

#include "tear/exec/memory.h"
#include "tear/exec/parallel.h"
#include "tear/math/types.h"

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <string>
#include <type_traits>
#include <typeindex>
#include <typeinfo>
#include <vector>

namespace tear {

// Number type of a frame-file column (io/ encodes tables of them).
enum class ColumnType { Int32, UInt8, Float32, Float64 };

// What a field is for.
enum class FieldRole {
  // Part of the restartable state: permuted with the particles, saved in checkpoints.
  State,
  // Recomputed every step from the state (this step's stresses): sized with the particles,
  // never saved or permuted.
  Scratch,
};

// How a field appears in frame files: one column per name (component k of the value; names
// beyond the value's components, e.g. z of a 2D position, are written as 0). No names: the
// field is not written.
struct FieldColumns {
  std::vector<std::string> names;
  ColumnType type = ColumnType::Float32;
};

struct FieldInfo {
  std::string name;  // unique in its store; checkpoints match fields by it
  FieldRole role = FieldRole::State;
  FieldColumns columns;
  // Optional fields exist (hold values) only in stores that enable them: state that only some
  // bodies need (the damage history, plastic state).
  bool optional = false;
};

// Shorthands for declarations.
inline FieldInfo state_field(std::string name, FieldColumns columns = {}) {
  return {std::move(name), FieldRole::State, std::move(columns), false};
}
inline FieldInfo optional_state_field(std::string name, FieldColumns columns = {}) {
  return {std::move(name), FieldRole::State, std::move(columns), true};
}
inline FieldInfo scratch_field(std::string name) {
  return {std::move(name), FieldRole::Scratch, {}, false};
}
inline FieldInfo optional_scratch_field(std::string name) {
  return {std::move(name), FieldRole::Scratch, {}, true};
}

// Components of a field value, for frame columns: scalars have one, vectors Dim; matrices none
// (not written).
template <class T>
struct FieldValue {
  static constexpr int kComponents = 1;
  static double component(const T& v, int) { return double(v); }
};
template <int Dim>
struct FieldValue<Vec<Dim>> {
  static constexpr int kComponents = Dim;
  static double component(const Vec<Dim>& v, int k) { return double(v[k]); }
};
template <int Dim>
struct FieldValue<Mat<Dim>> {
  static constexpr int kComponents = 0;
  static double component(const Mat<Dim>&, int) { return 0; }
};
// Index tuples (an element's vertices): not written as columns.
template <class T, size_t N>
struct FieldValue<std::array<T, N>> {
  static constexpr int kComponents = 0;
  static double component(const std::array<T, N>&, int) { return 0; }
};

// A store's list of fields. Entries are kept as offsets from the registry, so a copied or moved
// store (whose fields copy their values) lists its own fields without registering again.
class FieldRegistry {
 public:
  // One registered field, seen without its type.
  class Entry {
   public:
    const FieldInfo& info() const { return info_; }
    size_t element_bytes() const { return element_bytes_; }
    int components() const { return components_; }
    // The value of a new particle, as bytes (element_bytes() of them).
    const std::string& default_bytes() const { return default_; }
    // A derived entry stores nothing: it is frame columns computed from other fields.
    bool derived() const { return derived_ != nullptr; }

   private:
    friend class FieldRegistry;
    FieldInfo info_;
    ptrdiff_t offset_ = 0;  // of the std::vector<T> from the registry
    size_t element_bytes_ = 0;
    int components_ = 0;
    std::string default_;  // the value of a new particle, as bytes
    void (*derived_)(const FieldRegistry&, size_t, double*) = nullptr;
    size_t (*size_)(const void*) = nullptr;
    void (*resize_)(void*, size_t, const char* default_value) = nullptr;
    void (*reserve_)(void*, size_t) = nullptr;
    void (*release_)(void*) = nullptr;  // empty, with no storage
    size_t (*capacity_)(const void*) = nullptr;
    char* (*data_)(void*) = nullptr;  // resize first: the pointer is to the vector's storage
    // v[k] becomes v[order[k]]: gathered into the store's spare vector of the type, which
    // then swaps storage with v (no copy back).
    void (*permute_)(void*, const std::vector<uint32_t>& order, FieldRegistry* store) = nullptr;
    // Remove the elements at ascending indices `which`, keeping the others in order.
    void (*erase_)(void*, const std::vector<uint32_t>& which) = nullptr;
    // out[c][k] = column c of element rows[k], k < count, for the n_out frame columns.
    void (*columns_)(const void*, const uint32_t* rows, size_t count, int n_out,
                     double* const* out) = nullptr;
  };

  FieldRegistry() = default;
  FieldRegistry(const FieldRegistry&) = default;
  FieldRegistry(FieldRegistry&&) = default;
  FieldRegistry& operator=(const FieldRegistry&) = default;
  FieldRegistry& operator=(FieldRegistry&&) = default;

  // Particles: the size of the non-optional fields.
  size_t size() const;
  // Every enabled field to n particles (new ones hold their field's default value).
  void resize(size_t n);
  // Room for n particles without reallocating.
  void reserve(size_t n);
  // One particle more, every enabled field at its declared default; returns its index.
  size_t append();
  // Reorder the state fields: new index k holds old particle order[k]. Scratch fields are left
  // alone (they are recomputed before use).
  void permute(const std::vector<uint32_t>& order);
  // Remove particles `which` (ascending indices) from every enabled field, keeping the order of
  // the others.
  void erase(const std::vector<uint32_t>& which);

  // Enable an optional field (sized to the store; an optional derived entry starts writing its
  // columns); enabling an enabled field does nothing. Throws std::invalid_argument for a name
  // the store does not declare or that is not optional.
  void enable(const std::string& name);
  bool enabled(const std::string& name) const;
  // Disable an optional field: its storage is released. Throws like enable().
  void disable(const std::string& name);
  // Enable and disable the optional fields as `other` (a store of the same type) has them.
  void enable_like(const FieldRegistry& other);
  bool enabled(const Entry& e) const { return !e.info().optional || enabled_[index_of(e)]; }
  // Whether the entry holds values here: enabled and not derived.
  bool stored(const Entry& e) const;
  // Names of the optional entries with frame columns: what a run may add to its frames.
  std::vector<std::string> optional_columns() const;

  const std::vector<Entry>& entries() const { return entries_; }
  const Entry* find(const std::string& name) const;
  size_t field_size(const Entry& e) const { return e.size_(at(e)); }
  // The values of a field as bytes (element_bytes() each, host order): checkpoints.
  const char* field_data(const Entry& e) const {
    return e.data_(const_cast<void*>(at(e)));  // read only
  }
  // The bytes of particle i's value (element_bytes() of them), to write in place.
  char* element(const Entry& e, size_t i) { return e.data_(at(e)) + i * e.element_bytes_; }
  // Replace a field's values by `count` elements from `bytes` (element_bytes() each).
  void assign_field(const Entry& e, const char* bytes, size_t count);
  // Make a field `count` copies of one element (element_bytes() at `element`).
  void fill_field(const Entry& e, const char* element, size_t count);
  // The frame-column values of entry e (e.info().columns.names.size() of them; components
  // beyond the value's are 0) for particles rows[0 .. count): out[c][k] is column c of
  // particle rows[k].
  void columns(const Entry& e, const uint32_t* rows, size_t count, double* const* out) const;
  // The same for one particle i: out[c] is column c.
  void columns(const Entry& e, size_t i, double* out) const;

  // Bytes of one particle over the enabled fields (state and scratch).
  size_t bytes_per_particle() const;
  // Bytes held now by the enabled fields' storage.
  size_t memory_bytes() const;

 protected:
  // Called by Field<T>'s constructor: `field` is a member of the store deriving from this.
  template <class T>
  void add(std::vector<T>* field, FieldInfo info, T default_value);

 private:
  template <class T>
  friend class Field;
  friend class DerivedColumns;
  void add_derived(FieldColumns columns, void (*value)(const FieldRegistry&, size_t, double*),
                   bool optional);
  void* at(const Entry& e) { return reinterpret_cast<char*>(this) + e.offset_; }
  const void* at(const Entry& e) const { return reinterpret_cast<const char*>(this) + e.offset_; }
  size_t index_of(const Entry& e) const { return size_t(&e - entries_.data()); }
  // The entry of an optional field; throws std::invalid_argument for a name the store does not
  // declare or that is not optional.
  const Entry& optional_entry(const std::string& name) const;

  // permute's buffer for fields of type T (one per type, kept to avoid fresh pages every
  // reorder; after a reorder it holds a field's previous storage).
  template <class T>
  std::vector<T>& spare();

  // The spare vectors, one per field type. A copied store does not copy them (it makes its own
  // when it first reorders).
  class Spares {
   public:
    struct Spare {
      std::type_index type;
      std::shared_ptr<void> vector;            // a std::vector<type>
      size_t (*bytes)(const void*) = nullptr;  // its capacity in bytes
    };
    Spares() = default;
    Spares(const Spares&) {}
    Spares(Spares&&) = default;
    Spares& operator=(const Spares&) { return *this; }
    Spares& operator=(Spares&&) = default;
    std::vector<Spare> list;
  };

  std::vector<Entry> entries_;
  std::vector<char> enabled_;  // per entry; only read for optional ones
  Spares spares_;
};

// A per-particle field: a std::vector<T> that registers itself in its store at construction.
// T must be a plain value (checkpoints and reorders move bytes).
template <class T>
class Field : public std::vector<T> {
 public:
  // `default_value`: what a new particle holds (append, resize).
  Field(FieldRegistry* store, FieldInfo info, T default_value) {
    store->add<T>(this, std::move(info), default_value);
  }
  Field(const Field&) = default;
  Field(Field&&) = default;
  Field& operator=(const Field&) = default;
  Field& operator=(Field&&) = default;
  using std::vector<T>::operator=;
};

// Frame columns computed from a store's fields (the world-space fiber from F and the rest
// frame): declared like a field, stored nowhere. `value(store, i, out)` writes one number per
// column name. Optional ones are written only where the store enables them (by the first
// column's name).
class DerivedColumns {
 public:
  DerivedColumns(FieldRegistry* store, FieldColumns columns,
                 void (*value)(const FieldRegistry&, size_t, double*), bool optional = false) {
    store->add_derived(std::move(columns), value, optional);
  }
};

// ---- template definitions ----

template <class T>
void FieldRegistry::add(std::vector<T>* field, FieldInfo info, T default_value) {
  // Moved as bytes (reorders, checkpoints): plain values, fixed-size Eigen types included (not
  // "trivially copyable" by the trait only because they declare their copy constructors).
  static_assert(std::is_trivially_destructible_v<T> && std::is_standard_layout_v<T>,
                "particle fields are moved as bytes");
  using V = std::vector<T>;
  Entry e;
  e.info_ = std::move(info);
  e.offset_ = reinterpret_cast<char*>(field) - reinterpret_cast<char*>(this);
  e.element_bytes_ = sizeof(T);
  e.components_ = FieldValue<T>::kComponents;
  e.default_.assign(reinterpret_cast<const char*>(&default_value), sizeof(T));
  e.size_ = [](const void* f) { return static_cast<const V*>(f)->size(); };
  e.resize_ = [](void* f, size_t n, const char* def) {
    V& v = *static_cast<V*>(f);
    const size_t old = v.size();
    reserve_large(&v, n);
    v.resize(n);
    auto fill = [&](size_t a, size_t b) {
      for (size_t i = a; i < b; ++i) std::memcpy(static_cast<void*>(&v[i]), def, sizeof(T));
    };
    constexpr size_t kFill = 8192;  // elements per parallel chunk (first touch of large stores)
    if (n <= old + kFill) return fill(old, std::max(n, old));
    parallel_for((n - old + kFill - 1) / kFill, [&](size_t c) {
      fill(old + c * kFill, std::min(n, old + (c + 1) * kFill));
    });
  };
  e.reserve_ = [](void* f, size_t n) { reserve_large(static_cast<V*>(f), n); };
  e.release_ = [](void* f) { V().swap(*static_cast<V*>(f)); };
  e.capacity_ = [](const void* f) { return static_cast<const V*>(f)->capacity(); };
  e.data_ = [](void* f) { return reinterpret_cast<char*>(static_cast<V*>(f)->data()); };
  e.columns_ = [](const void* f, const uint32_t* rows, size_t count, int n_out,
                  double* const* out) {
    const V& v = *static_cast<const V*>(f);
    for (int c = 0; c < n_out; ++c) {
      double* column = out[c];
      if (c >= FieldValue<T>::kComponents) {
        std::fill(column, column + count, 0.0);
        continue;
      }
      for (size_t k = 0; k < count; ++k) column[k] = FieldValue<T>::component(v[rows[k]], c);
    }
  };
  e.permute_ = [](void* f, const std::vector<uint32_t>& order, FieldRegistry* store) {
    V& v = *static_cast<V*>(f);
    V& spare = store->spare<T>();
    const size_t n = order.size();
    reserve_large(&spare, n);
    spare.resize(n);
    T* out = spare.data();
    const T* in = v.data();
    parallel_for(
        n, [&](size_t k) { std::memcpy(static_cast<void*>(out + k), in + order[k], sizeof(T)); });
    v.swap(spare);
  };
  e.erase_ = [](void* f, const std::vector<uint32_t>& which) {
    V& v = *static_cast<V*>(f);
    size_t kept = 0, w = 0;
    for (size_t i = 0; i < v.size(); ++i) {
      if (w < which.size() && which[w] == i) {
        ++w;
        continue;
      }
      if (kept != i) v[kept] = v[i];
      ++kept;
    }
    v.resize(kept);
  };
  entries_.push_back(std::move(e));
  enabled_.push_back(0);
}

template <class T>
std::vector<T>& FieldRegistry::spare() {
  for (Spares::Spare& s : spares_.list)
    if (s.type == std::type_index(typeid(T))) return *static_cast<std::vector<T>*>(s.vector.get());
  spares_.list.push_back({std::type_index(typeid(T)), std::make_shared<std::vector<T>>(),
                          [](const void* v) {
                            return static_cast<const std::vector<T>*>(v)->capacity() * sizeof(T);
                          }});
  return *static_cast<std::vector<T>*>(spares_.list.back().vector.get());
}

}  // namespace tear
