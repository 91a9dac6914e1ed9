#include "mpm/colliders/contact.h"

#include "core/error.h"
#include "core/json_util.h"

namespace nsf {

ContactRule parse_contact(const nlohmann::json& obj, const std::string& path) {
  namespace js = nsf::json;
  ContactRule rule;
  std::string mode = js::get_string(obj, path, "contact", "slip");
  if (mode == "sticky") {
    rule.mode = Contact::Sticky;
  } else if (mode == "slip") {
    rule.mode = Contact::Slip;
  } else if (mode == "friction") {
    rule.mode = Contact::Friction;
  } else {
    fail("scene: '", js::child(path, "contact"), "' = \"", mode,
         "\" is not a contact mode; use \"sticky\", \"slip\" or \"friction\"");
  }
  if (rule.mode == Contact::Friction) {
    rule.friction = js::get_number(obj, path, "friction", js::non_negative());
  } else if (obj.contains("friction")) {
    fail("scene: '", js::child(path, "friction"), "' only applies with \"contact\": \"friction\" (",
         js::child(path, "contact"), " is \"", mode, "\")");
  }
  return rule;
}

void apply_contact(const ContactRule& rule, const Vec3& n, const Vec3& vc, Vec3& v) {
  if (rule.mode == Contact::Sticky) {
    v = vc;
    return;
  }
  Vec3 vrel = v - vc;
  double vn = vrel.dot(n);
  if (vn >= 0.0) return;  // separating: the obstacle does not pull
  Vec3 vt = vrel - vn * n;
  if (rule.mode == Contact::Friction) {
    double vt_norm = vt.norm();
    if (vt_norm <= -rule.friction * vn) {
      vt.setZero();
    } else {
      vt += rule.friction * vn * vt / vt_norm;
    }
  }
  v = vc + vt;
}

}  // namespace nsf
