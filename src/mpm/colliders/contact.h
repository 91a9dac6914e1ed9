#pragma once
// The contact rule shared by rigid colliders and the domain walls: what happens to a grid node's
// velocity once the node is found inside an obstacle.
#include <nlohmann/json.hpp>
#include <string>

#include "core/types.h"
#include "mpm/colliders/collider.h"

namespace nsf {

struct ContactRule {
  Contact mode = Contact::Slip;
  double friction = 0.0;  // Coulomb coefficient μ_f, used by Contact::Friction only
};

// Reads the optional "contact" and "friction" keys of `obj` (at `path`). "friction" is required
// with "contact": "friction" and rejected with the other modes, where it would be ignored.
ContactRule parse_contact(const nlohmann::json& obj, const std::string& path);

// Makes the node velocity v (in/out) obey the rule against an obstacle whose outward unit normal
// is n and whose own velocity at the node is vc.
//  sticky:   v = vc
//  slip:     the normal part of v − vc is removed if the node approaches (v_rel·n < 0)
//  friction: slip, then Coulomb friction on the tangential part:
//            ‖v_t‖ ≤ −μ_f v_n → v_t = 0, else v_t += μ_f v_n v_t/‖v_t‖
void apply_contact(const ContactRule& rule, const Vec3& n, const Vec3& vc, Vec3& v);

}  // namespace nsf
