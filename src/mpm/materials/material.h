#pragma once
// A constitutive model: an elastic energy plus an optional plastic return map (App. F).
// Models register under a string key, so a scene's "type": "drucker_prager" finds its class
// without an if/else chain to edit.
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/types.h"
#include "mpm/material_point.h"

namespace nsf {

// Scalar parameters as written in the scene ("E", "nu", "friction_angle", ...).
using ParamMap = std::map<std::string, double>;

class Material {
 public:
  virtual ~Material() = default;
  virtual std::string type() const = 0;

  // Parameter names this model accepts, with their meaning (for errors and docs).
  virtual std::vector<std::string> parameter_names() const = 0;

  // Builds the per-particle record from scene parameters. Throws nsf::Error naming `path` and the
  // key for unknown keys, missing keys or out-of-range values.
  virtual MaterialPoint make_point(const ParamMap& params, const std::string& path) const = 0;

  // Return map + stress: projects the trial deformation gradient F (in/out) onto the admissible
  // set, updates the plastic state in `mp`, and returns the Kirchhoff stress τ(F^E).
  // `dt` is the time step (rate-dependent models use it).
  virtual Mat3 update(Mat3& F, MaterialPoint& mp, double dt) const = 0;

  // Largest stiffness λ+2μ a particle may have, for the CFL bound on the elastic wave speed.
  static double p_wave_modulus(const MaterialPoint& mp) { return mp.lambda + 2.0 * mp.mu; }
};

using MaterialFactory = std::function<std::unique_ptr<Material>()>;

// Registry keyed by the scene's "type" string.
void register_material(const std::string& type, MaterialFactory factory);
std::unique_ptr<Material> make_material(const std::string& type);  // throws on unknown type
std::vector<std::string> material_types();

// Lamé parameters from Young's modulus and Poisson ratio (App. F table).
inline double shear_modulus(double E, double nu) {
  return E / (2.0 * (1.0 + nu));
}
inline double lame_lambda(double E, double nu) {
  return E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
}
inline double bulk_modulus(double E, double nu) {
  return E / (3.0 * (1.0 - 2.0 * nu));
}

}  // namespace nsf
