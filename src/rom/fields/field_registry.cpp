#include <map>
#include <mutex>

#include "core/error.h"
#include "core/strings.h"
#include "rom/fields/field_source.h"
#include "rom/fields/sources.h"

namespace nsf {

namespace {

// Built-in sources are listed here: self-registering statics would be dropped by the linker from
// a static library.
struct Tables {
  std::map<std::string, DeformationFactory> deformation = {
      {"network", make_network_deformation},
      {"basis", make_basis_deformation},
  };
  std::map<std::string, PointFieldFactory> stress = {
      {"network", make_network_stress},
      {"basis", make_basis_stress},
      {"crom", make_crom_stress},
      {"tracked", make_tracked_stress},
  };
  std::map<std::string, PointFieldFactory> affine = {
      {"network", make_network_affine},
      {"basis", make_basis_affine},
      {"none", make_zero_affine},
      {"tracked", make_tracked_affine},
  };
  std::map<std::string, VelocityFactory> velocity = {
      {"latent", make_latent_velocity},
      {"tracked", make_tracked_velocity},
  };
  std::map<std::string, PointFieldFactory>& of(FieldRole role) {
    return role == FieldRole::stress ? stress : affine;
  }
};

Tables& tables() {
  static Tables t;
  return t;
}

std::mutex& tables_mutex() {
  static std::mutex m;
  return m;
}

template <typename Map>
std::vector<std::string> names_of(const Map& m) {
  std::vector<std::string> out;
  for (const auto& entry : m) out.push_back(entry.first);
  return out;
}

template <typename Map>
const typename Map::mapped_type& find(const Map& m, const std::string& name, const char* what) {
  const auto it = m.find(name);
  if (it == m.end()) {
    const std::string record = retired_field_source(what, name);
    if (!record.empty())
      fail("rom: the ", what, " source '", name, "' was retired (it lost: docs/experiments/",
           record, ")");
    fail("rom: unknown ", what, " source '", name, "' (known: ", join(names_of(m)), ")");
  }
  return it->second;
}

// A copy of the factory, taken under the lock, is called outside it: a factory may build
// sources that look up others.
template <typename Map>
auto make(Map& m, const std::string& name, const char* what, const FieldContext& context) {
  typename Map::mapped_type factory;
  {
    std::lock_guard<std::mutex> lock(tables_mutex());
    factory = find(m, name, what);
  }
  return factory(context);
}

const char* role_name(FieldRole role) {
  return role == FieldRole::stress ? "stress" : "affine";
}

}  // namespace

void register_deformation_source(const std::string& name, DeformationFactory factory) {
  std::lock_guard<std::mutex> lock(tables_mutex());
  tables().deformation[name] = std::move(factory);
}

void register_point_field_source(FieldRole role, const std::string& name,
                                 PointFieldFactory factory) {
  std::lock_guard<std::mutex> lock(tables_mutex());
  tables().of(role)[name] = std::move(factory);
}

void register_velocity_source(const std::string& name, VelocityFactory factory) {
  std::lock_guard<std::mutex> lock(tables_mutex());
  tables().velocity[name] = std::move(factory);
}

std::unique_ptr<DeformationSource> make_deformation_source(const std::string& name,
                                                           const FieldContext& context) {
  return make(tables().deformation, name, "deformation", context);
}

std::unique_ptr<PointFieldSource> make_point_field_source(FieldRole role, const std::string& name,
                                                          const FieldContext& context) {
  return make(tables().of(role), name, role_name(role), context);
}

std::unique_ptr<VelocitySource> make_velocity_source(const std::string& name,
                                                     const FieldContext& context) {
  return make(tables().velocity, name, "velocity", context);
}

std::vector<std::string> deformation_source_names() {
  std::lock_guard<std::mutex> lock(tables_mutex());
  return names_of(tables().deformation);
}

std::vector<std::string> point_field_source_names(FieldRole role) {
  std::lock_guard<std::mutex> lock(tables_mutex());
  return names_of(tables().of(role));
}

std::string retired_field_source(const std::string& role, const std::string& name) {
  // The code last lived at commit 6a0656ca4713.
  if (name == "tangent" && (role == "deformation" || role == "stress" || role == "affine"))
    return "2026-11-22-tangent-cache.md";
  if (name == "velocity" && role == "affine") return "2026-11-22-velocity-affine.md";
  return "";
}

std::vector<std::string> velocity_source_names() {
  std::lock_guard<std::mutex> lock(tables_mutex());
  return names_of(tables().velocity);
}

}  // namespace nsf
