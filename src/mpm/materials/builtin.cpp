#include "mpm/materials/builtin.h"

#include "mpm/materials/fixed_corotated.h"

namespace nsf {

std::map<std::string, MaterialFactory> builtin_materials() {
  return {
      {"fixed_corotated", [] { return std::make_unique<FixedCorotated>(); }},
  };
}

}  // namespace nsf
