#include "rom/setup/rom_section.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <utility>

#include "core/error.h"
#include "core/strings.h"
#include "rom/calibration/rom_calibration.h"
#include "rom/fields/field_source.h"
#include "rom/step/sampling.h"

namespace nsf {

namespace {
const char* const kFamilies[] = {"mlp", "basis"};

// rom.KEY as a number above 0 (or from 0 with zero_allowed).
double number_at(const char* key, const nlohmann::json& v, bool zero_allowed, const char* meaning) {
  if (!v.is_number() || !(zero_allowed ? v.get<double>() >= 0 : v.get<double>() > 0) ||
      !std::isfinite(v.get<double>()))
    fail("scene key 'rom.", key, "' must be a ", zero_allowed ? "non-negative" : "positive",
         " number (", meaning, "), got ", v.dump());
  return v.get<double>();
}

// rom.KEY as a whole number in [lo, hi].
int integer_at(const char* key, const nlohmann::json& v, int lo, int hi, const char* meaning) {
  if (!v.is_number_integer() || v.get<double>() < lo || v.get<double>() > hi)
    fail("scene key 'rom.", key, "' must be a whole number from ", lo, " to ", hi, " (", meaning,
         "), got ", v.dump());
  return v.get<int>();
}

void read_dt_ratio(const char* key, const nlohmann::json& v, RomSection& s) {
  s.dt_ratio = v == "cfl" ? RomOptions::kDtRatioAtCfl
                          : number_at(key, v, false, "the ROM step over simulation.dt, or \"cfl\"");
}

void read_cfl(const char* key, const nlohmann::json& v, RomSection& s) {
  s.cfl = number_at(key, v, false, "the CFL factor the tracked state's step is held to");
  if (*s.cfl > 1)
    fail(
        "scene key 'rom.cfl' must be at most 1 (an elastic wave crosses less than a cell per "
        "step), got ",
        *s.cfl);
}

void read_grid(const char* key, const nlohmann::json& v, RomSection& s) {
  s.grid = number_at(key, v, false, "the ROM grid's spacing over the scene's dx");
  if (*s.grid < 1)
    fail("scene key 'rom.grid' must be at least 1 (the ROM's grid is the scene's or coarser), got ",
         *s.grid);
}

void read_rigid_frames(const char*, const nlohmann::json& v, RomSection& s) {
  std::vector<int> objects;
  const bool listed = v.is_array() && std::all_of(v.begin(), v.end(), [](const auto& o) {
                        return o.is_number_integer() && o.template get<double>() >= 0 &&
                               o.template get<double>() < 65536;
                      });
  if (listed) objects = v.get<std::vector<int>>();
  std::sort(objects.begin(), objects.end());
  if (!listed || std::adjacent_find(objects.begin(), objects.end()) != objects.end())
    fail(
        "scene key 'rom.rigid_frames' must be a list of distinct object indices (the objects "
        "that move in rigid frames of their own), got ",
        v.dump());
  s.rigid_frames = objects;
}

void read_fields(const char*, const nlohmann::json& f, RomSection& s) {
  if (!f.is_object()) fail("scene key 'rom.fields' must be an object, got ", f.dump());
  for (const auto& [key, v] : f.items()) {
    std::string* slot = key == "deformation" ? &s.fields.deformation
                        : key == "stress"    ? &s.fields.stress
                        : key == "affine"    ? &s.fields.affine
                        : key == "velocity"  ? &s.fields.velocity
                                             : nullptr;
    if (!slot)
      fail("scene key 'rom.fields.", key,
           "' is unknown (known: deformation, stress, affine, velocity)");
    if (!v.is_string() || v.get<std::string>().empty())
      fail("scene key 'rom.fields.", key, "' must be a field source's name, got ", v.dump());
    const std::string record = retired_field_source(key, v.get<std::string>());
    if (!record.empty())
      fail("scene key 'rom.fields.", key, "': the source ", v.dump(),
           " was retired (it lost: docs/experiments/", record, ")");
    *slot = v.get<std::string>();
  }
}

void read_profile(const char*, const nlohmann::json& v, RomSection& s) {
  if (!v.is_string() || (v != "auto" && v != "family" && v != "unseen"))
    fail("scene key 'rom.profile' must be \"auto\", \"family\" or \"unseen\", got ", v.dump());
  s.profile = v.get<std::string>();
}

// The keys parse_rom_section reads itself, each with its reader, in the order they are read; the
// settings objects (read: null) are overlaid after them; the sampling reads the rest
// (sampling_keys()).
struct SectionKey {
  const char* key;
  void (*read)(const char* key, const nlohmann::json& v, RomSection& s);
};
const SectionKey kSectionKeys[] = {
    {"dt_ratio", read_dt_ratio},
    {"quadrature",
     [](const char* key, const nlohmann::json& v, RomSection& s) {
       s.quadrature =
           integer_at(key, v, 0, 1000, "integration points per grid cell; 0: every particle");
     }},
    {"gn_iterations",
     [](const char* key, const nlohmann::json& v, RomSection& s) {
       s.gn_iterations = integer_at(key, v, 1, 100, "the Gauss-Newton iteration cap");
     }},
    {"gn_damping",
     [](const char* key, const nlohmann::json& v, RomSection& s) {
       s.gn_damping = number_at(key, v, true, "the Levenberg-Marquardt damping of the fit's step");
     }},
    {"cfl", read_cfl},
    {"grid", read_grid},
    {"rigid_frames", read_rigid_frames},
    {"fields", read_fields},
    {"latent_prior",
     [](const char* key, const nlohmann::json& v, RomSection& s) {
       s.latent_prior = number_at(key, v, true, "the latent prior's length in metres; 0: none");
     }},
    {"profile", read_profile},
    {"tracked", nullptr},
    {"unseen", nullptr},
    {"mlp", nullptr},
    {"basis", nullptr}};

std::vector<std::string> known_keys() {
  std::vector<std::string> keys = sampling_keys();
  for (const SectionKey& k : kSectionKeys) keys.push_back(k.key);
  return keys;
}

// A settings object rom.KEY (a decoder family's, or the tracked state's): `base` with it merged
// over, parsed as a section of its own. `what` names whose settings it holds; it may hold none of
// the objects `nested`.
std::shared_ptr<const RomSection> overlay(const nlohmann::json& base, const nlohmann::json& own,
                                          const std::string& key, const std::string& what,
                                          std::initializer_list<const char*> nested) {
  if (!own.is_object())
    fail("scene key 'rom.", key, "' must be an object of rom settings for ", what, ", got ",
         own.dump());
  for (const char* n : nested)
    if (own.contains(n))
      fail("scene key 'rom.", key, ".", n, "': the settings for ", what, " hold no ", n,
           " object (a family's tracked settings go in rom.FAMILY.tracked)");
  nlohmann::json merged = base;
  merged.merge_patch(own);
  try {
    return std::make_shared<const RomSection>(parse_rom_section(merged));
  } catch (const Error& e) {
    fail("in scene key 'rom.", key, "': ", e.what());
  }
}
}  // namespace

RomSection parse_rom_section(const nlohmann::json& rom) {
  RomSection s;
  if (rom.is_null()) return s;
  if (!rom.is_object()) fail("scene key 'rom' must be an object, got ", rom.dump());
  const std::vector<std::string> known = known_keys();
  for (const auto& item : rom.items())
    if (std::find(known.begin(), known.end(), item.key()) == known.end())
      fail("unknown scene key 'rom.", item.key(), "' (known: ", join(known), ")");
  // What is left once this function has taken its own keys is the sampling's.
  nlohmann::json sampling = rom;
  for (const SectionKey& k : kSectionKeys) {
    if (!rom.contains(k.key)) continue;
    if (k.read) k.read(k.key, rom.at(k.key), s);
    sampling.erase(k.key);
  }
  // A family's object merges over the common settings, its tracked object over theirs (so a
  // tracked setting wins over a family's plain one).
  nlohmann::json common = rom;
  for (const char* family : kFamilies) common.erase(family);
  nlohmann::json plain = common;
  plain.erase("tracked");
  plain.erase("unseen"), common.erase("unseen");
  s.sampling = parse_sampling(sampling);
  if (rom.contains("tracked")) {
    const nlohmann::json& own = rom.at("tracked");
    if (own.is_object() && own.contains("fields") && own.at("fields").is_object() &&
        own.at("fields").contains("stress"))
      fail(
          "scene key 'rom.tracked.fields.stress': the tracked settings are for the tracked "
          "stress; set the stress source in rom.fields");
    s.tracked = overlay(plain, own, "tracked", "a run with the tracked state",
                        {"mlp", "basis", "tracked", "unseen"});
  }
  if (rom.contains("unseen"))
    s.unseen =
        overlay(plain, rom.at("unseen"), "unseen", "a run outside the model's training family",
                {"mlp", "basis", "tracked", "unseen"});
  for (const char* family : kFamilies)
    if (rom.contains(family))
      (parse_family(family, "rom") == DecoderFamily::mlp ? s.mlp : s.basis) =
          overlay(common, rom.at(family), family,
                  std::string("a model with ") + family + " decoders", {"mlp", "basis", "unseen"});
  return s;
}

const RomSection& RomSection::for_family(DecoderFamily family) const {
  if (family == DecoderFamily::mlp && mlp) return *mlp;
  if (family == DecoderFamily::basis && basis) return *basis;
  return *this;
}

bool RomSection::tracks_stress(DecoderFamily family, const std::string& stress) const {
  return (stress.empty() ? for_family(family).fields.stress : stress) == "tracked";
}

const RomSection& RomSection::for_run(DecoderFamily family, const std::string& stress) const {
  const RomSection& f = for_family(family);
  return f.tracked && tracks_stress(family, stress) ? *f.tracked : f;
}

ModelCalibration calibration_of(const NeuralFields& fields, const RomSection& rom,
                                const std::string& stress) {
  const RomCalibrations c = rom_calibrations(fields);
  if (rom.tracks_stress(fields.family(), stress) && c.tracked.latent_prior >= 0)
    return {c.tracked.latent_prior, c.tracked.dt_ratio};
  return {c.decoded.latent_prior, c.decoded.dt_ratio};
}

ModelCalibration unseen_calibration_of(const NeuralFields& fields) {
  const RomCalibration c = rom_calibrations(fields).unseen;
  return {c.latent_prior, c.dt_ratio};
}

RomOptions with_rom_section(RomOptions o, const RomSection& s, const ModelCalibration& calibrated) {
  o.sampling = s.sampling;
  o.dt_ratio = s.dt_ratio.value_or(calibrated.dt_ratio > 0 ? calibrated.dt_ratio : o.dt_ratio);
  o.latent_prior = s.latent_prior.value_or(calibrated.latent_prior >= 0 ? calibrated.latent_prior
                                                                        : o.latent_prior);
  o.quadrature_per_cell = s.quadrature.value_or(o.quadrature_per_cell);
  o.inversion.max_iterations = s.gn_iterations.value_or(o.inversion.max_iterations);
  o.inversion.damping = s.gn_damping.value_or(o.inversion.damping);
  o.cfl = s.cfl.value_or(o.cfl);
  o.grid_factor = s.grid.value_or(o.grid_factor);
  o.rigid_frames = s.rigid_frames.value_or(o.rigid_frames);
  for (auto [mine, scenes] : {std::pair{&o.fields.deformation, &s.fields.deformation},
                              std::pair{&o.fields.stress, &s.fields.stress},
                              std::pair{&o.fields.affine, &s.fields.affine},
                              std::pair{&o.fields.velocity, &s.fields.velocity}})
    if (mine->empty()) *mine = *scenes;
  return o;
}

std::vector<std::string> overrides_hidden_by(const nlohmann::json& rom, const std::string& profile,
                                             const std::vector<std::string>& overrides) {
  std::vector<std::string> hidden;
  if (!rom.is_object() || !rom.contains(profile) || !rom.at(profile).is_object()) return hidden;
  const nlohmann::json& own = rom.at(profile);
  for (const std::string& o : overrides) {
    const size_t eq = o.find('=');
    if (o.rfind("rom.", 0) != 0 || eq == std::string::npos) continue;
    const std::string key = o.substr(4, eq - 4);
    if (key.find('.') == std::string::npos && own.contains(key))
      hidden.push_back("--set " + o + " does not reach this run: the scene's rom." + profile + "." +
                       key + " = " + own.at(key).dump() + " wins (set rom." + profile + "." + key +
                       " instead)");
  }
  return hidden;
}

RomSettingSources rom_setting_sources(const RomSection& s, const ModelCalibration& calibrated,
                                      bool prior_given, bool dt_ratio_given) {
  const auto source = [](bool given, bool scene, bool model) {
    return given ? "command line" : scene ? "scene" : model ? "model" : "default";
  };
  return {source(prior_given, bool(s.latent_prior), calibrated.latent_prior >= 0),
          source(dt_ratio_given, bool(s.dt_ratio), calibrated.dt_ratio > 0)};
}

}  // namespace nsf
