#include "mpm/scene/object_builder.h"

#include <algorithm>
#include <limits>
#include <random>

#include "core/error.h"
#include "core/json_util.h"
#include "mpm/scene/sampling.h"
#include "mpm/scene/scene_keys.h"
#include "mpm/scene/shape_json.h"

namespace nsf {
namespace {

using Json = nlohmann::json;
namespace js = nsf::json;

struct ObjectMaterial {
  uint16_t index;  // into Scene::materials
  MaterialPoint point;
};

ObjectMaterial parse_material(const Json& obj, const std::string& path, Scene& scene) {
  const std::string mpath = js::child(path, "material");
  if (!obj.contains("material")) fail("scene: missing required key '", mpath, "'");
  const Json& m = obj.at("material");
  std::string type = js::get_string(m, mpath, "type");
  ParamMap params;
  for (auto it = m.begin(); it != m.end(); ++it) {
    if (it.key() == "type") continue;
    if (!it.value().is_number())
      fail("scene: '", js::child(mpath, it.key()), "' must be a number, got ", it.value().dump());
    params[it.key()] = it.value().get<double>();
  }
  auto same_type = [&](const std::unique_ptr<Material>& mat) { return mat->type() == type; };
  auto found = std::find_if(scene.materials.begin(), scene.materials.end(), same_type);
  if (found == scene.materials.end()) {
    try {
      scene.materials.push_back(make_material(type));
    } catch (const Error& e) {
      fail("scene: '", js::child(mpath, "type"), "': ", e.what());
    }
    found = scene.materials.end() - 1;
  }
  ObjectMaterial out;
  out.index = static_cast<uint16_t>(found - scene.materials.begin());
  out.point = (*found)->make_point(params, mpath);
  return out;
}

struct WeakRegion {
  ShapePtr shape;
  double stiffness_scale = 1.0;
  double yield_scale = 1.0;
  // Which particles are weak, scattered (the paper's App. B, "weak elements perturbed"): each
  // particle is tested at its position moved by up to `jitter` times the object's extent along
  // each axis, uniformly at random from `jitter_seed`, in particle order (reproducible).
  double jitter = 0;
  std::mt19937_64 rng;
  std::string path;
  bool used = false;

  bool holds(const Vec3& p, const Vec3& extent) {
    if (jitter == 0) return shape->contains(p);
    Vec3 moved = p;
    for (int a = 0; a < 3; ++a) {  // u in [-1, 1), from the top 53 bits: the same on every machine
      const double u = 2.0 * double(rng() >> 11) * 0x1.0p-53 - 1.0;
      moved[a] += jitter * extent[a] * u;
    }
    return shape->contains(moved);
  }
};

std::vector<WeakRegion> parse_weak_regions(const Json& obj, const std::string& path,
                                           const ShapeContext& context) {
  std::vector<WeakRegion> out;
  if (!obj.contains("weak_regions")) return out;
  const std::string wpath = js::child(path, "weak_regions");
  const Json& w = obj.at("weak_regions");
  if (!w.is_array()) fail("scene: '", wpath, "' must be an array, got ", w.dump());
  for (size_t i = 0; i < w.size(); ++i) {
    WeakRegion r;
    r.path = js::child(wpath, i);
    js::check_keys(w[i], r.path,
                   {"shape", "stiffness_scale", "yield_scale", "jitter", "jitter_seed"});
    if (!w[i].contains("stiffness_scale") && !w[i].contains("yield_scale"))
      fail("scene: weak region '", r.path,
           "' sets neither 'stiffness_scale' nor 'yield_scale', so it would do nothing");
    if (!w[i].contains("shape"))
      fail("scene: missing required key '", js::child(r.path, "shape"), "'");
    r.shape = parse_shape(w[i].at("shape"), js::child(r.path, "shape"), context);
    r.stiffness_scale = js::get_number(w[i], r.path, "stiffness_scale", 1.0, js::non_negative());
    r.yield_scale = js::get_number(w[i], r.path, "yield_scale", 1.0, js::non_negative());
    r.jitter = js::get_number(w[i], r.path, "jitter", 0.0, js::closed(0, 1));
    r.rng.seed(uint64_t(js::get_number(w[i], r.path, "jitter_seed", 1.0, js::closed(0, 1e15))));
    out.push_back(std::move(r));
  }
  return out;
}

// Particles must keep clear of the wall node layers, or the wall would act inside the object.
void check_inside_domain(const std::vector<Vec3>& pts, const std::string& path,
                         const SimSettings& s) {
  const double margin = s.wall_nodes * s.dx;
  const Vec3 lo = s.domain_lo.array() + margin, hi = s.domain_hi.array() - margin;
  Vec3 pmin = Vec3::Constant(std::numeric_limits<double>::infinity()), pmax = -pmin;
  for (const Vec3& p : pts) {
    pmin = pmin.cwiseMin(p);
    pmax = pmax.cwiseMax(p);
  }
  // The sampler clips at the domain faces, so a clipped object shows up here as well.
  if ((pmin.array() < lo.array()).any() || (pmax.array() > hi.array()).any())
    fail("scene: '", js::child(path, "shape"),
         "' reaches outside the usable domain: its particles ", "span [", pmin.transpose(),
         "] to [", pmax.transpose(), "], but must lie within [", lo.transpose(), "] to [",
         hi.transpose(), "] (", s.wall_nodes, " cells inside the domain faces, which are wall)");
}

}  // namespace

void add_object(const Json& obj, const std::string& path, size_t index, const ShapeContext& context,
                Scene& scene) {
  const SimSettings& s = scene.settings;
  js::check_keys(obj, path, object_keys());
  if (!obj.contains("shape")) fail("scene: missing required key '", js::child(path, "shape"), "'");
  ShapePtr shape = parse_shape(obj.at("shape"), js::child(path, "shape"), context);
  ObjectMaterial mat = parse_material(obj, path, scene);
  const double density = js::get_number(obj, path, "density", s.density, js::positive());
  const Vec3 v0 = js::get_vec3(obj, path, "velocity", Vec3::Zero());
  const Vec3 omega = js::get_vec3(obj, path, "angular_velocity", Vec3::Zero());
  std::vector<WeakRegion> weak = parse_weak_regions(obj, path, context);

  const Lattice lattice{s.domain_lo, s.domain_hi, s.dx, s.ppc};
  std::vector<Vec3> pts = sample_shape(*shape, lattice);
  if (pts.empty())
    fail("scene: '", js::child(path, "shape"), "' contains no particles (is it thinner than the ",
         "particle spacing ", lattice.spacing(), ", or outside the domain?)");
  check_inside_domain(pts, path, s);

  // Equal particle masses: the centre of mass is the mean position.
  Vec3 com = Vec3::Zero();
  for (const Vec3& p : pts) com += p;
  com /= static_cast<double>(pts.size());

  // The object's extent, which scales a weak region's jitter.
  Vec3 lo = pts.front(), hi = pts.front();
  for (const Vec3& p : pts) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const Vec3 extent = hi - lo;

  const double V = lattice.particle_volume();
  Particles& P = scene.particles;
  for (const Vec3& p : pts) {
    MaterialPoint mp = mat.point;
    // Overlapping regions compound: their scales multiply.
    for (WeakRegion& r : weak) {
      if (!r.holds(p, extent)) continue;
      r.used = true;
      mp.mu *= r.stiffness_scale;
      mp.lambda *= r.stiffness_scale;
      mp.yield_stress *= r.yield_scale;
    }
    P.add(p, v0 + omega.cross(p - com), density * V, V, mp, mat.index,
          static_cast<uint16_t>(index));
  }
  for (const WeakRegion& r : weak)
    if (!r.used)
      fail("scene: '", js::child(r.path, "shape"), "' contains none of the particles of '", path,
           "'; a weak region must overlap its object");
}

}  // namespace nsf
