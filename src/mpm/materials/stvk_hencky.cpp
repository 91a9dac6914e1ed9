#include "mpm/materials/stvk_hencky.h"

#include "core/svd3.h"
#include "mpm/materials/hencky.h"
#include "mpm/materials/param_check.h"
#include "mpm/materials/principal.h"

namespace nsf {

MaterialPoint StvkHencky::make_point(const ParamMap& params, const std::string& path) const {
  ParamReader r(params, path, parameter_names());
  MaterialPoint mp = r.elastic_point();
  return mp;
}

Mat3 StvkHencky::update(Mat3& F, MaterialPoint& mp, double /*dt*/) const {
  Mat3 U, V;
  Vec3 s;
  svd3(F, U, s, V);
  return from_principal(U, hencky::principal_kirchhoff(hencky::log_strain(s), mp.mu, mp.lambda));
}

}  // namespace nsf
