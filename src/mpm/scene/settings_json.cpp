#include "mpm/scene/settings_json.h"

#include <cmath>

#include "core/error.h"
#include "core/json_util.h"
#include "mpm/colliders/contact.h"

namespace nsf {
namespace {

namespace js = nsf::json;

Transfer parse_transfer(const std::string& s, const std::string& path) {
  if (s == "apic") return Transfer::APIC;
  if (s == "pic") return Transfer::PIC;
  if (s == "rpic") return Transfer::RPIC;
  fail("scene: '", path, "' = \"", s,
       "\" is not a transfer scheme; use \"apic\", \"pic\" or \"rpic\"");
}

// Guards against a typo such as dx=1e-5 allocating an absurd grid.
constexpr double kMaxGridNodes = 1e9;

void check_domain(const SimSettings& s, const std::string& path) {
  for (int a = 0; a < 3; ++a)
    if (!(s.domain_hi[a] > s.domain_lo[a]))
      fail("scene: '", js::child(path, "domain_hi"), "' = [", s.domain_hi.transpose(),
           "] must exceed 'domain_lo' = [", s.domain_lo.transpose(), "] on every axis");
  double nodes = 1;
  const int min_cells = 2 * s.wall_nodes + 1;
  for (int a = 0; a < 3; ++a) {
    double cells = (s.domain_hi[a] - s.domain_lo[a]) / s.dx;
    if (cells < min_cells)
      fail("scene: '", js::child(path, "dx"), "' = ", s.dx, " leaves only ", cells,
           " cells along axis ", "xyz"[a], "; the domain needs at least ", min_cells,
           " (the outer ", s.wall_nodes, " node layers of each face are wall)");
    nodes *= std::ceil(cells) + 1;
  }
  if (nodes > kMaxGridNodes)
    fail("scene: '", js::child(path, "dx"), "' = ", s.dx, " gives ", nodes,
         " grid nodes, more than the limit of ", kMaxGridNodes);
}

}  // namespace

SimSettings parse_settings(const nlohmann::json& j, const std::string& path) {
  js::check_keys(j, path,
                 {"domain_lo", "domain_hi", "dx", "dt", "frames", "substeps", "ppc", "density",
                  "gravity", "transfer", "cfl", "walls"});
  SimSettings s;
  s.domain_lo = js::get_vec3(j, path, "domain_lo", s.domain_lo);
  s.domain_hi = js::get_vec3(j, path, "domain_hi", s.domain_hi);
  s.dx = js::get_number(j, path, "dx", js::positive());
  s.dt = js::get_number(j, path, "dt", js::positive());
  s.frames = js::get_int(j, path, "frames", s.frames, 1, 10'000'000);
  s.substeps = js::get_int(j, path, "substeps", s.substeps, 1, 10'000'000);
  s.ppc = js::get_int(j, path, "ppc", s.ppc, 1, 16);
  s.density = js::get_number(j, path, "density", s.density, js::positive());
  s.gravity = js::get_vec3(j, path, "gravity", s.gravity);
  s.transfer =
      parse_transfer(js::get_string(j, path, "transfer", "apic"), js::child(path, "transfer"));
  s.cfl = js::get_number(j, path, "cfl", s.cfl, {0.0, 1.0, true, false});
  if (j.contains("walls")) {
    std::string wpath = js::child(path, "walls");
    js::check_keys(j.at("walls"), wpath, {"contact", "friction"});
    ContactRule rule = parse_contact(j.at("walls"), wpath);
    s.wall_contact = rule.mode;
    s.wall_friction = rule.friction;
  }
  check_domain(s, path);
  return s;
}

}  // namespace nsf
