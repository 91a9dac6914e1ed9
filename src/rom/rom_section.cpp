#include "rom/rom_section.h"

#include <cmath>

#include "core/error.h"

namespace nsf {

RomSection parse_rom_section(const nlohmann::json& rom) {
  RomSection s;
  if (rom.is_null()) return s;
  if (!rom.is_object()) fail("scene key 'rom' must be an object, got ", rom.dump());
  nlohmann::json sampling = rom;
  // The keys that are not the sampling's: each a number, checked against its lower bound.
  const auto number = [&](const char* key, bool zero_allowed, const char* meaning) {
    std::optional<double> out;
    if (!rom.contains(key)) return out;
    const nlohmann::json& v = rom.at(key);
    if (!v.is_number() || !(zero_allowed ? v.get<double>() >= 0 : v.get<double>() > 0) ||
        !std::isfinite(v.get<double>()))
      fail("scene key 'rom.", key, "' must be a ", zero_allowed ? "non-negative" : "positive",
           " number (", meaning, "), got ", v.dump());
    sampling.erase(key);
    return out = v.get<double>();
  };
  s.dt_ratio = number("dt_ratio", false, "the ROM step over simulation.dt");
  s.latent_prior = number("latent_prior", true, "the latent prior's length in metres; 0: none");
  s.sampling = parse_sampling(sampling);
  return s;
}

}  // namespace nsf
