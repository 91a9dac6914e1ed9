#include "core/json_util.h"

#include <cmath>
#include <sstream>

#include "core/error.h"

namespace nsf::json {

std::string child(const std::string& path, const std::string& key) {
  return path.empty() ? key : path + "." + key;
}
std::string child(const std::string& path, size_t index) {
  return path + "[" + std::to_string(index) + "]";
}

void require_object(const json& j, const std::string& path) {
  if (!j.is_object())
    fail("scene: '", path.empty() ? "<root>" : path, "' must be a JSON object, got ", j.dump());
}

void check_keys(const json& obj, const std::string& path, const std::vector<std::string>& allowed) {
  require_object(obj, path);
  for (auto it = obj.begin(); it != obj.end(); ++it) {
    bool ok = false;
    for (const auto& a : allowed) ok = ok || it.key() == a;
    if (!ok) {
      std::ostringstream known;
      for (const auto& a : allowed) known << (known.tellp() > 0 ? ", " : "") << a;
      std::string value = it.value().dump();
      if (value.size() > 60) value = value.substr(0, 57) + "...";
      fail("scene: unknown key '", child(path, it.key()), "' (= ", value,
           "; allowed here: ", known.str(), ")");
    }
  }
}

void check_keys(const json& obj, const std::string& path,
                std::initializer_list<const char*> allowed) {
  check_keys(obj, path, std::vector<std::string>(allowed.begin(), allowed.end()));
}

void check_range(double v, const std::string& path, Range r) {
  bool ok = std::isfinite(v);
  if (ok) ok = r.lo_open ? v > r.lo : v >= r.lo;
  if (ok) ok = r.hi_open ? v < r.hi : v <= r.hi;
  if (!ok) {
    std::ostringstream want;
    want << (r.lo_open ? "(" : "[") << r.lo << ", " << r.hi << (r.hi_open ? ")" : "]");
    fail("scene: '", path, "' = ", v, " is out of range; it must lie in ", want.str());
  }
}

static const json& need(const json& obj, const std::string& path, const char* key) {
  require_object(obj, path);
  auto it = obj.find(key);
  if (it == obj.end()) fail("scene: missing required key '", child(path, key), "'");
  return *it;
}

static double as_number(const json& v, const std::string& p) {
  if (!v.is_number()) fail("scene: '", p, "' must be a number, got ", v.dump());
  return v.get<double>();
}

double get_number(const json& obj, const std::string& path, const char* key, Range r) {
  std::string p = child(path, key);
  double v = as_number(need(obj, path, key), p);
  check_range(v, p, r);
  return v;
}

double get_number(const json& obj, const std::string& path, const char* key, double fallback,
                  Range r) {
  if (!obj.contains(key)) return fallback;
  return get_number(obj, path, key, r);
}

int get_int(const json& obj, const std::string& path, const char* key, int lo, int hi) {
  std::string p = child(path, key);
  const json& v = need(obj, path, key);
  if (!v.is_number_integer()) fail("scene: '", p, "' must be an integer, got ", v.dump());
  long long x = v.get<long long>();
  if (x < lo || x > hi)
    fail("scene: '", p, "' = ", x, " is out of range; it must lie in [", lo, ", ", hi, "]");
  return static_cast<int>(x);
}

int get_int(const json& obj, const std::string& path, const char* key, int fallback, int lo,
            int hi) {
  if (!obj.contains(key)) return fallback;
  return get_int(obj, path, key, lo, hi);
}

std::string get_string(const json& obj, const std::string& path, const char* key) {
  const json& v = need(obj, path, key);
  if (!v.is_string()) fail("scene: '", child(path, key), "' must be a string, got ", v.dump());
  return v.get<std::string>();
}

std::string get_string(const json& obj, const std::string& path, const char* key,
                       const std::string& fallback) {
  if (!obj.contains(key)) return fallback;
  return get_string(obj, path, key);
}

bool get_bool(const json& obj, const std::string& path, const char* key, bool fallback) {
  if (!obj.contains(key)) return fallback;
  const json& v = obj.at(key);
  if (!v.is_boolean())
    fail("scene: '", child(path, key), "' must be true or false, got ", v.dump());
  return v.get<bool>();
}

Vec3 get_vec3(const json& obj, const std::string& path, const char* key) {
  std::string p = child(path, key);
  const json& v = need(obj, path, key);
  if (!v.is_array() || v.size() != 3)
    fail("scene: '", p, "' must be an array of 3 numbers, got ", v.dump());
  Vec3 out;
  for (int i = 0; i < 3; ++i) {
    out[i] = as_number(v[i], child(p, static_cast<size_t>(i)));
    check_range(out[i], child(p, static_cast<size_t>(i)), {});
  }
  return out;
}

Vec3 get_vec3(const json& obj, const std::string& path, const char* key, const Vec3& fallback) {
  if (!obj.contains(key)) return fallback;
  return get_vec3(obj, path, key);
}

}  // namespace nsf::json
