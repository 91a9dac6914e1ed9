#include "mpm/colliders/rigid_motion.h"

#include <algorithm>
#include <limits>

#include "core/error.h"
#include "core/json_util.h"
#include "core/rotation.h"

namespace nsf {
namespace js = nsf::json;

RigidMotion::RigidMotion(const Vec3& center, const Mat3& rotation)
    : center0_(center), rotation0_(rotation) {}

RigidMotion RigidMotion::parse(const nlohmann::json& collider, const std::string& path,
                               const Vec3& center, const Mat3& rotation) {
  RigidMotion m(center, rotation);
  if (!collider.contains("motion")) return m;
  const std::string mpath = js::child(path, "motion");
  const nlohmann::json& j = collider.at("motion");
  js::check_keys(j, mpath, {"velocity", "angular_velocity", "start", "end", "keyframes"});

  if (j.contains("keyframes")) {
    for (const char* k : {"velocity", "angular_velocity", "start", "end"})
      if (j.contains(k))
        fail("scene: '", js::child(mpath, k), "' cannot be combined with '",
             js::child(mpath, "keyframes"), "'; use one kind of motion");
    const std::string kpath = js::child(mpath, "keyframes");
    const nlohmann::json& keys = j.at("keyframes");
    if (!keys.is_array() || keys.empty())
      fail("scene: '", kpath, "' must be a non-empty array of keyframes, got ", keys.dump());
    for (size_t i = 0; i < keys.size(); ++i) {
      const std::string p = js::child(kpath, i);
      js::check_keys(keys[i], p, {"t", "center", "rotate_deg"});
      Keyframe k;
      k.t = js::get_number(keys[i], p, "t");
      if (!m.keys_.empty() && !(k.t > m.keys_.back().t))
        fail("scene: '", js::child(p, "t"), "' = ", k.t,
             " must be later than the previous keyframe's t = ", m.keys_.back().t);
      k.center = js::get_vec3(keys[i], p, "center", center);
      k.rotation =
          keys[i].contains("rotate_deg")
              ? Eigen::Quaterniond(rotation_from_euler_deg(js::get_vec3(keys[i], p, "rotate_deg")))
              : Eigen::Quaterniond(rotation);
      m.keys_.push_back(k);
    }
    return m;
  }

  m.velocity_ = js::get_vec3(j, mpath, "velocity", Vec3::Zero());
  m.angular_velocity_ = js::get_vec3(j, mpath, "angular_velocity", Vec3::Zero());
  m.start_ = js::get_number(j, mpath, "start", 0.0, js::non_negative());
  m.end_ = std::numeric_limits<double>::infinity();
  if (j.contains("end")) {
    m.end_ = js::get_number(j, mpath, "end");
    if (!(m.end_ > m.start_))
      fail("scene: '", js::child(mpath, "end"), "' = ", m.end_,
           " must be later than 'start' = ", m.start_);
  }
  return m;
}

RigidPose RigidMotion::at(double t) const {
  return keys_.empty() ? at_velocity(t) : at_keyframes(t);
}

RigidPose RigidMotion::at_velocity(double t) const {
  RigidPose p;
  double tau = std::clamp(t - start_, 0.0, end_ - start_);
  p.center = center0_ + velocity_ * tau;
  double w = angular_velocity_.norm();
  p.rotation =
      w > 0 ? Mat3(Eigen::AngleAxisd(w * tau, angular_velocity_ / w) * rotation0_) : rotation0_;
  if (t >= start_ && t < end_) {
    p.velocity = velocity_;
    p.angular_velocity = angular_velocity_;
  }
  return p;
}

RigidPose RigidMotion::at_keyframes(double t) const {
  RigidPose p;
  if (t <= keys_.front().t || keys_.size() == 1) {
    p.center = keys_.front().center;
    p.rotation = keys_.front().rotation.toRotationMatrix();
    return p;
  }
  if (t >= keys_.back().t) {
    p.center = keys_.back().center;
    p.rotation = keys_.back().rotation.toRotationMatrix();
    return p;
  }
  size_t i = 1;
  while (keys_[i].t <= t) ++i;  // keys_[i-1].t <= t < keys_[i].t
  const Keyframe& a = keys_[i - 1];
  const Keyframe& b = keys_[i];
  double span = b.t - a.t, s = (t - a.t) / span;
  p.center = a.center + s * (b.center - a.center);
  p.rotation = a.rotation.slerp(s, b.rotation).toRotationMatrix();
  p.velocity = (b.center - a.center) / span;
  // slerp turns at a constant rate about a fixed axis: that of the relative rotation b·a⁻¹
  // (taken the short way round, as slerp does).
  Eigen::Quaterniond rel = b.rotation * a.rotation.conjugate();
  if (rel.w() < 0) rel.coeffs() *= -1.0;
  Eigen::AngleAxisd aa(rel);
  p.angular_velocity = aa.axis() * (aa.angle() / span);
  return p;
}

}  // namespace nsf
