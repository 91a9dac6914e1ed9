#include "rom/rom_section.h"

#include "core/error.h"

namespace nsf {

RomSection parse_rom_section(const nlohmann::json& rom) {
  RomSection s;
  if (rom.is_null()) return s;
  if (!rom.is_object()) fail("scene key 'rom' must be an object, got ", rom.dump());
  nlohmann::json sampling = rom;
  if (rom.contains("dt_ratio")) {
    const nlohmann::json& v = rom.at("dt_ratio");
    if (!v.is_number() || !(v.get<double>() > 0))
      fail(
          "scene key 'rom.dt_ratio' must be a positive number (the ROM step over "
          "simulation.dt), got ",
          v.dump());
    s.dt_ratio = v.get<double>();
    sampling.erase("dt_ratio");
  }
  s.sampling = parse_sampling(sampling);
  return s;
}

}  // namespace nsf
