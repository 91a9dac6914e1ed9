#pragma once
// Reads and validates a material's scalar parameters, with errors naming the scene key.
#include <string>
#include <vector>

#include "core/error.h"
#include "core/json_util.h"
#include "mpm/materials/material.h"

namespace nsf {

inline json::Range positive_range() {
  return json::positive();
}
inline json::Range poisson_range() {
  return {-1.0, 0.5, true, true};
}

class ParamReader {
 public:
  // Rejects any key of `params` not in `allowed`.
  ParamReader(const ParamMap& params, std::string path, const std::vector<std::string>& allowed)
      : params_(params), path_(std::move(path)) {
    for (const auto& [k, v] : params) {
      bool ok = false;
      for (const auto& a : allowed) ok = ok || a == k;
      if (!ok) {
        std::string known;
        for (const auto& a : allowed) known += (known.empty() ? "" : ", ") + a;
        fail("scene: unknown material parameter '", json::child(path_, k),
             "' (this model takes: ", known, ")");
      }
    }
  }
  double get(const std::string& key, json::Range r) const {
    auto it = params_.find(key);
    if (it == params_.end())
      fail("scene: missing material parameter '", json::child(path_, key), "'");
    json::check_range(it->second, json::child(path_, key), r);
    return it->second;
  }
  double get(const std::string& key, double fallback, json::Range r) const {
    return params_.count(key) ? get(key, r) : fallback;
  }
  // Every model's elasticity: Lamé parameters from "E" and "nu" (App. F table).
  MaterialPoint elastic_point() const {
    const double E = get("E", positive_range());
    const double nu = get("nu", poisson_range());
    MaterialPoint mp;
    mp.mu = shear_modulus(E, nu);
    mp.lambda = lame_lambda(E, nu);
    return mp;
  }

 private:
  const ParamMap& params_;
  std::string path_;
};

}  // namespace nsf
