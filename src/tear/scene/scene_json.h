// scene/: strict JSON reading helpers for the scene parser (internal to scene/).
// Every accessor checks presence, type and shape, and throws SceneError naming the JSON path.
#pragma once

#include "tear/scene/scene.h"

#include <initializer_list>
#include <optional>
#include <string>

namespace tear::scene_detail {

using nlohmann::json;

std::string key_path(const std::string& parent, const std::string& key);
std::string index_path(const std::string& parent, size_t index);
// Shortest round-trip text of a number, as JSON writes it (0.7, 1e+30, 3).
std::string num_str(double v);
// Edit distance counting an adjacent transposition as one edit ("materails" -> "materials").
size_t edit_distance(const std::string& a, const std::string& b);
// ", did you mean \"KEY\"?" for the candidate closest to `key` when it is a likely typo, else "".
template <class Range>
std::string did_you_mean(const std::string& key, const Range& candidates) {
  std::string best;
  size_t best_d = size_t(-1);
  for (const auto& c : candidates) {
    size_t d = edit_distance(key, c);
    if (d < best_d) best_d = d, best = c;
  }
  // At most 2 edits, and fewer than half the key's length ("E" is no typo of "x").
  if (best_d <= 2 && 2 * best_d < key.size()) return ", did you mean \"" + best + "\"?";
  return "";
}
// "1 entry", "3 entries": the size of an array, for error messages.
std::string entries(size_t n);
// "a number", "a string", "an object", ... for error messages.
std::string type_desc(const json& j);

// Reads one scene document. `dim` is known once the top-level "dim" has been read.
class Reader {
 public:
  explicit Reader(std::string file) : file_(std::move(file)) {}
  const std::string& file() const { return file_; }
  int dim = 2;

  [[noreturn]] void fail(const std::string& path, const std::string& reason) const;

  // Checks that `j` is an object whose keys are all in `allowed`.
  void object(const json& j, const std::string& path,
              std::initializer_list<const char*> allowed) const;
  // The value at obj[key], or nullptr when absent or null.
  const json* find(const json& obj, const char* key) const;

  // Typed fields of object `obj` (at `path`). Without a default, a missing field is an error.
  double number(const json& obj, const std::string& path, const char* key,
                std::optional<double> def = std::nullopt) const;
  long long integer(const json& obj, const std::string& path, const char* key,
                    std::optional<long long> def = std::nullopt) const;
  bool boolean(const json& obj, const std::string& path, const char* key,
               std::optional<bool> def = std::nullopt) const;
  std::string string(const json& obj, const std::string& path, const char* key,
                     std::optional<std::string> def = std::nullopt) const;
  // A string that must be one of `options`; returns its index.
  int choice(const json& obj, const std::string& path, const char* key,
             std::initializer_list<const char*> options,
             std::optional<int> def = std::nullopt) const;
  // A vector of exactly `dim` numbers (z = 0 in 2D).
  Vec3d vec(const json& obj, const std::string& path, const char* key,
            std::optional<Vec3d> def = std::nullopt) const;
  // The same checks on a value already found (for array items and scalars-or-arrays).
  double as_number(const json& v, const std::string& path) const;
  Vec3d as_vec(const json& v, const std::string& path, int n) const;

  // Range checks with uniform messages ("must be > 0, got -1").
  void check(bool ok, const std::string& path, const std::string& reason) const {
    if (!ok) fail(path, reason);
  }
  void positive(double v, const std::string& path) const;
  void non_negative(double v, const std::string& path) const;
  // An integer at obj[key] in [lo, hi] ("must be in [1, 100000], got 0").
  long long integer_in(const json& obj, const std::string& path, const char* key, long long lo,
                       long long hi, std::optional<long long> def = std::nullopt) const;

 private:
  std::string file_;
};

// JSON of the first `dim` entries of v.
json vec_json(const Vec3d& v, int dim);

}  // namespace tear::scene_detail
