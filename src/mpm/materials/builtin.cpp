#include "mpm/materials/builtin.h"

#include "mpm/materials/drucker_prager.h"
#include "mpm/materials/fixed_corotated.h"
#include "mpm/materials/herschel_bulkley.h"
#include "mpm/materials/stvk_hencky.h"
#include "mpm/materials/von_mises.h"

namespace nsf {

std::map<std::string, MaterialFactory> builtin_materials() {
  return {
      {"fixed_corotated", [] { return std::make_unique<FixedCorotated>(); }},
      {"stvk_hencky", [] { return std::make_unique<StvkHencky>(); }},
      {"drucker_prager", [] { return std::make_unique<DruckerPrager>(); }},
      {"von_mises", [] { return std::make_unique<VonMises>(); }},
      {"herschel_bulkley", [] { return std::make_unique<HerschelBulkley>(); }},
  };
}

}  // namespace nsf
