#include "mpm/scene/shape_json.h"

#include <filesystem>
#include <functional>
#include <map>

#include "core/error.h"
#include "core/json_util.h"
#include "core/rotation.h"
#include "mpm/scene/mesh/mesh_io.h"
#include "mpm/scene/mesh/mesh_shape.h"

namespace nsf {
namespace {

using Json = nlohmann::json;
namespace js = nsf::json;

ShapePtr parse_box(const Json& j, const std::string& path) {
  js::check_keys(j, path, {"type", "min", "max", "center", "size", "transform"});
  bool corners = j.contains("min") || j.contains("max");
  bool centred = j.contains("center") || j.contains("size");
  if (corners == centred)
    fail("scene: box '", path, "' needs either \"min\" and \"max\" or \"center\" and \"size\"");
  if (corners) {
    Vec3 lo = js::get_vec3(j, path, "min"), hi = js::get_vec3(j, path, "max");
    for (int a = 0; a < 3; ++a)
      if (!(hi[a] > lo[a]))
        fail("scene: '", js::child(path, "max"), "' = ", j.at("max").dump(),
             " must exceed 'min' = ", j.at("min").dump(), " on every axis");
    return make_box(lo, hi);
  }
  Vec3 c = js::get_vec3(j, path, "center"), size = js::get_vec3(j, path, "size");
  for (int a = 0; a < 3; ++a)
    js::check_range(size[a], js::child(js::child(path, "size"), static_cast<size_t>(a)),
                    js::positive());
  return make_box(c - 0.5 * size, c + 0.5 * size);
}

ShapePtr parse_sphere(const Json& j, const std::string& path) {
  js::check_keys(j, path, {"type", "center", "radius", "transform"});
  return make_sphere(js::get_vec3(j, path, "center"),
                     js::get_number(j, path, "radius", js::positive()));
}

ShapePtr parse_cylinder(const Json& j, const std::string& path) {
  js::check_keys(j, path, {"type", "center", "radius", "height", "axis", "transform"});
  return make_cylinder(js::get_vec3(j, path, "center"),
                       js::get_number(j, path, "radius", js::positive()),
                       js::get_number(j, path, "height", js::positive()),
                       axis_index(js::get_string(j, path, "axis", "y"), js::child(path, "axis")));
}

ShapePtr parse_capsule(const Json& j, const std::string& path) {
  js::check_keys(j, path, {"type", "a", "b", "radius", "transform"});
  return make_capsule(js::get_vec3(j, path, "a"), js::get_vec3(j, path, "b"),
                      js::get_number(j, path, "radius", js::positive()));
}

ShapePtr parse_torus(const Json& j, const std::string& path) {
  js::check_keys(j, path, {"type", "center", "major_radius", "minor_radius", "axis", "transform"});
  return make_torus(js::get_vec3(j, path, "center"),
                    js::get_number(j, path, "major_radius", js::positive()),
                    js::get_number(j, path, "minor_radius", js::positive()),
                    axis_index(js::get_string(j, path, "axis", "y"), js::child(path, "axis")));
}

ShapePtr parse_csg(CsgOp op, size_t min_children, const Json& j, const std::string& path,
                   const ShapeContext& context) {
  js::check_keys(j, path, {"type", "children", "transform"});
  std::string cpath = js::child(path, "children");
  if (!j.contains("children")) fail("scene: missing required key '", cpath, "'");
  const Json& c = j.at("children");
  if (!c.is_array() || c.size() < min_children)
    fail("scene: '", cpath, "' must be an array of at least ", min_children, " shapes, got ",
         c.dump());
  ShapeContext inner = context;
  ++inner.depth;
  std::vector<ShapePtr> children;
  for (size_t i = 0; i < c.size(); ++i)
    children.push_back(parse_shape(c[i], js::child(cpath, i), inner));
  return make_csg(op, std::move(children));
}

// Scale may be one number (uniform) or one per axis.
Vec3 parse_scale(const Json& t, const std::string& path) {
  if (!t.contains("scale")) return Vec3::Ones();
  std::string p = js::child(path, "scale");
  Vec3 s;
  if (t.at("scale").is_number()) {
    s = Vec3::Constant(js::get_number(t, path, "scale", js::positive()));
  } else {
    s = js::get_vec3(t, path, "scale");
    for (int a = 0; a < 3; ++a)
      js::check_range(s[a], js::child(p, static_cast<size_t>(a)), js::positive());
  }
  return s;
}

// A triangle-mesh file; "scale" (like transform.scale) converts its units before any transform.
ShapePtr parse_mesh(const Json& j, const std::string& path, const ShapeContext& context) {
  js::check_keys(j, path, {"type", "file", "scale", "transform"});
  const std::string name = js::get_string(j, path, "file");
  std::filesystem::path file(name);
  if (file.is_relative() && !context.base_dir.empty()) file = context.base_dir / file;
  TriangleMesh mesh = read_triangle_mesh(file.string(), js::child(path, "file"));
  const Vec3 scale = parse_scale(j, path);
  for (Vec3& v : mesh.vertices) v = v.cwiseProduct(scale);
  return make_mesh_shape(std::move(mesh));
}

ShapePtr apply_transform(ShapePtr shape, const Json& j, const std::string& path) {
  if (!j.contains("transform")) return shape;
  std::string tpath = js::child(path, "transform");
  const Json& t = j.at("transform");
  js::check_keys(t, tpath, {"translate", "rotate_deg", "scale"});
  Vec3 translate = js::get_vec3(t, tpath, "translate", Vec3::Zero());
  Mat3 R = rotation_from_euler_deg(js::get_vec3(t, tpath, "rotate_deg", Vec3::Zero()));
  return make_transformed(std::move(shape), translate, R, parse_scale(t, tpath));
}

using Parser = std::function<ShapePtr(const Json&, const std::string&, const ShapeContext&)>;

// Primitives need nothing from the context.
template <ShapePtr (*parse)(const Json&, const std::string&)>
ShapePtr primitive(const Json& j, const std::string& path, const ShapeContext&) {
  return parse(j, path);
}

template <CsgOp op, size_t min_children>
ShapePtr csg(const Json& j, const std::string& path, const ShapeContext& context) {
  return parse_csg(op, min_children, j, path, context);
}

const std::map<std::string, Parser>& parsers() {
  static const std::map<std::string, Parser> table = {
      {"box", primitive<parse_box>},
      {"sphere", primitive<parse_sphere>},
      {"cylinder", primitive<parse_cylinder>},
      {"capsule", primitive<parse_capsule>},
      {"torus", primitive<parse_torus>},
      {"mesh", parse_mesh},
      {"union", csg<CsgOp::Union, 1>},
      {"intersection", csg<CsgOp::Intersection, 1>},
      {"difference", csg<CsgOp::Difference, 2>},
  };
  return table;
}

}  // namespace

ShapePtr parse_shape(const Json& j, const std::string& path, const ShapeContext& context) {
  if (context.depth > kMaxShapeDepth)
    fail("scene: '", path, "' nests CSG shapes more than ", kMaxShapeDepth,
         " levels deep, the most nsf accepts");
  js::require_object(j, path);
  std::string type = js::get_string(j, path, "type");
  auto it = parsers().find(type);
  if (it == parsers().end()) {
    std::string known;
    for (const auto& [k, p] : parsers()) known += (known.empty() ? "" : ", ") + k;
    fail("scene: '", js::child(path, "type"), "' = \"", type, "\" is not a shape (known: ", known,
         ")");
  }
  return apply_transform(it->second(j, path, context), j, path);
}

}  // namespace nsf
