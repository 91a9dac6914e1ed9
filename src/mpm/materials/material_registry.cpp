#include <algorithm>
#include <mutex>

#include "core/error.h"
#include "mpm/materials/builtin.h"
#include "mpm/materials/material.h"

namespace nsf {
namespace {

std::map<std::string, MaterialFactory>& table() {
  // Built-in models are listed explicitly: self-registering statics are dropped by the linker
  // when libnsf is linked statically.
  static std::map<std::string, MaterialFactory> t = builtin_materials();
  return t;
}
std::mutex& table_mutex() {
  static std::mutex m;
  return m;
}

}  // namespace

void register_material(const std::string& type, MaterialFactory factory) {
  std::lock_guard<std::mutex> lock(table_mutex());
  table()[type] = std::move(factory);
}

std::unique_ptr<Material> make_material(const std::string& type) {
  std::lock_guard<std::mutex> lock(table_mutex());
  auto it = table().find(type);
  if (it == table().end()) {
    std::string known;
    for (const auto& [k, f] : table()) known += (known.empty() ? "" : ", ") + k;
    fail("unknown material type '", type, "' (known: ", known, ")");
  }
  return it->second();
}

std::vector<std::string> material_types() {
  std::lock_guard<std::mutex> lock(table_mutex());
  std::vector<std::string> out;
  for (const auto& [k, f] : table()) out.push_back(k);
  return out;
}

}  // namespace nsf
