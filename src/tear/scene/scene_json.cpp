#include "tear/scene/scene_json.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace tear::scene_detail {

// Optimal string alignment distance.
size_t edit_distance(const std::string& a, const std::string& b) {
  const size_t n = a.size(), m = b.size();
  std::vector<std::vector<size_t>> d(n + 1, std::vector<size_t>(m + 1));
  for (size_t i = 0; i <= n; ++i) d[i][0] = i;
  for (size_t j = 0; j <= m; ++j) d[0][j] = j;
  for (size_t i = 1; i <= n; ++i)
    for (size_t j = 1; j <= m; ++j) {
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1,
                          d[i - 1][j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[n][m];
}

std::string key_path(const std::string& parent, const std::string& key) {
  return parent.empty() ? key : parent + "." + key;
}

std::string index_path(const std::string& parent, size_t index) {
  return parent + "[" + std::to_string(index) + "]";
}

std::string num_str(double v) {
  if (v == std::floor(v) && std::abs(v) < 1e15) return std::to_string((long long)v);
  return json(v).dump();
}

std::string entries(size_t n) { return std::to_string(n) + (n == 1 ? " entry" : " entries"); }

std::string type_desc(const json& j) {
  switch (j.type()) {
    case json::value_t::null: return "null";
    case json::value_t::object: return "an object";
    case json::value_t::array: return "an array";
    case json::value_t::string: return "a string";
    case json::value_t::boolean: return "a boolean";
    case json::value_t::number_float: return "a number (" + j.dump() + ")";
    case json::value_t::number_integer:
    case json::value_t::number_unsigned: return "an integer (" + j.dump() + ")";
    default: return "an unsupported value";
  }
}

json vec_json(const Vec3d& v, int dim) {
  json a = json::array();
  for (int i = 0; i < dim; ++i) a.push_back(v[i]);
  return a;
}

void Reader::fail(const std::string& path, const std::string& reason) const {
  throw SceneError(file_, path, reason);
}

void Reader::object(const json& j, const std::string& path,
                    std::initializer_list<const char*> allowed) const {
  if (!j.is_object()) fail(path, "must be an object, got " + type_desc(j));
  for (auto it = j.begin(); it != j.end(); ++it) {
    bool known = false;
    for (const char* a : allowed) known = known || it.key() == a;
    if (!known) {
      std::string list;
      for (const char* a : allowed) list += std::string(list.empty() ? "" : ", ") + a;
      std::string hint = did_you_mean(it.key(), allowed);
      fail(key_path(path, it.key()), "unknown key" + hint + " (expected one of: " + list + ")");
    }
  }
}

const json* Reader::find(const json& obj, const char* key) const {
  auto it = obj.find(key);
  if (it == obj.end() || it->is_null()) return nullptr;
  return &*it;
}

double Reader::as_number(const json& v, const std::string& path) const {
  if (!v.is_number()) fail(path, "must be a number, got " + type_desc(v));
  double x = v.get<double>();
  if (!std::isfinite(x)) fail(path, "must be finite");
  return x;
}

Vec3d Reader::as_vec(const json& v, const std::string& path, int n) const {
  if (!v.is_array() || int(v.size()) != n)
    fail(path, "must be an array of " + std::to_string(n) + " numbers, got " +
                   (v.is_array() ? entries(v.size()) : type_desc(v)));
  Vec3d out = Vec3d::Zero();
  for (int i = 0; i < n; ++i) out[i] = as_number(v[i], index_path(path, i));
  return out;
}

double Reader::number(const json& obj, const std::string& path, const char* key,
                      std::optional<double> def) const {
  const json* v = find(obj, key);
  if (!v) {
    if (!def) fail(key_path(path, key), "required");
    return *def;
  }
  return as_number(*v, key_path(path, key));
}

long long Reader::integer(const json& obj, const std::string& path, const char* key,
                          std::optional<long long> def) const {
  const json* v = find(obj, key);
  std::string p = key_path(path, key);
  if (!v) {
    if (!def) fail(p, "required");
    return *def;
  }
  if (v->is_number_unsigned() &&
      v->get<unsigned long long>() > (unsigned long long)std::numeric_limits<long long>::max())
    fail(p, "too large, got " + v->dump());
  if (v->is_number_integer()) return v->get<long long>();
  // 4.0 is accepted as 4; 4.5 is not.
  if (v->is_number_float()) {
    double x = v->get<double>();
    if (std::isfinite(x) && x == std::floor(x) && std::abs(x) < 9e15) return (long long)x;
  }
  fail(p, "must be an integer, got " + type_desc(*v));
}

bool Reader::boolean(const json& obj, const std::string& path, const char* key,
                     std::optional<bool> def) const {
  const json* v = find(obj, key);
  if (!v) {
    if (!def) fail(key_path(path, key), "required");
    return *def;
  }
  if (!v->is_boolean()) fail(key_path(path, key), "must be true or false, got " + type_desc(*v));
  return v->get<bool>();
}

std::string Reader::string(const json& obj, const std::string& path, const char* key,
                           std::optional<std::string> def) const {
  const json* v = find(obj, key);
  if (!v) {
    if (!def) fail(key_path(path, key), "required");
    return *def;
  }
  if (!v->is_string()) fail(key_path(path, key), "must be a string, got " + type_desc(*v));
  return v->get<std::string>();
}

int Reader::choice(const json& obj, const std::string& path, const char* key,
                   std::initializer_list<const char*> options, std::optional<int> def) const {
  std::optional<std::string> sdef;
  if (def) sdef = options.begin()[*def];
  std::string s = string(obj, path, key, sdef);
  int i = 0;
  std::string list;
  for (const char* o : options) {
    if (s == o) return i;
    list += std::string(i++ ? ", " : "") + o;
  }
  fail(key_path(path, key), "unknown value \"" + s + "\" (expected one of: " + list + ")");
}

Vec3d Reader::vec(const json& obj, const std::string& path, const char* key,
                  std::optional<Vec3d> def) const {
  const json* v = find(obj, key);
  if (!v) {
    if (!def) fail(key_path(path, key), "required");
    return *def;
  }
  return as_vec(*v, key_path(path, key), dim);
}

void Reader::positive(double v, const std::string& path) const {
  check(v > 0, path, "must be > 0, got " + num_str(v));
}

void Reader::non_negative(double v, const std::string& path) const {
  check(v >= 0, path, "must be >= 0, got " + num_str(v));
}

long long Reader::integer_in(const json& obj, const std::string& path, const char* key,
                             long long lo, long long hi, std::optional<long long> def) const {
  const long long n = integer(obj, path, key, def);
  check(n >= lo && n <= hi, key_path(path, key),
        "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " + std::to_string(n));
  return n;
}

}  // namespace tear::scene_detail
