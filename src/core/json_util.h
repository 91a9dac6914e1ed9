#pragma once
// Validated reads from a JSON scene. Every error names the full key path ("objects[1].material.E")
// and the offending value, because that is what a user needs to fix a scene file.
#include <initializer_list>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/types.h"

namespace nsf::json {

using nlohmann::json;

// Path of a child key, e.g. child("objects[1]", "material") -> "objects[1].material".
std::string child(const std::string& path, const std::string& key);
std::string child(const std::string& path, size_t index);

// Rejects keys not in `allowed` (typos must not be silently ignored).
void check_keys(const json& obj, const std::string& path,
                std::initializer_list<const char*> allowed);
void check_keys(const json& obj, const std::string& path, const std::vector<std::string>& allowed);
void require_object(const json& j, const std::string& path);

struct Range {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false;  // true: value must be > lo, false: >= lo
  bool hi_open = false;
};
inline Range positive() {
  return {0.0, std::numeric_limits<double>::infinity(), true, false};
}
inline Range non_negative() {
  return {0.0, std::numeric_limits<double>::infinity(), false, false};
}
inline Range closed(double lo, double hi) {
  return {lo, hi, false, false};
}

double get_number(const json& obj, const std::string& path, const char* key, Range r = {});
double get_number(const json& obj, const std::string& path, const char* key, double fallback,
                  Range r = {});
int get_int(const json& obj, const std::string& path, const char* key, int lo, int hi);
int get_int(const json& obj, const std::string& path, const char* key, int fallback, int lo,
            int hi);
std::string get_string(const json& obj, const std::string& path, const char* key);
std::string get_string(const json& obj, const std::string& path, const char* key,
                       const std::string& fallback);
bool get_bool(const json& obj, const std::string& path, const char* key, bool fallback);
Vec3 get_vec3(const json& obj, const std::string& path, const char* key);
Vec3 get_vec3(const json& obj, const std::string& path, const char* key, const Vec3& fallback);

// Checks a number already read against a range; used by the two get_number overloads.
void check_range(double v, const std::string& path, Range r);

}  // namespace nsf::json
