#pragma once
// The camera of a software-rendered picture as the rasterisers need it: an orthonormal basis,
// world → pixel projection, and the ray through a pixel. Shared by the particle splatter and
// the collider ray caster so both agree on depth to the last bit.
#include <cmath>

#include "core/error.h"
#include "core/types.h"

namespace nsf {

struct Camera {
  Vec3 eye = Vec3(1.6, 1.3, 2.2);
  Vec3 target = Vec3(0.5, 0.4, 0.5);
  Vec3 up = Vec3(0, 1, 0);
  double fov_deg = 0;         // vertical field of view; 0 = orthographic
  double ortho_height = 1.2;  // orthographic only: world-space height of the picture
};

// Camera basis and projection for a picture of w x h (supersampled) pixels. Depth is measured
// along the viewing direction `fwd`, for particles and colliders alike.
struct View {
  Vec3 eye, fwd, right, up;
  bool perspective = false;
  double focal = 1;  // pixels per world unit at depth 1 (perspective) or everywhere (ortho)
  double cx = 0, cy = 0;

  View(const Camera& cam, int w, int h) : eye(cam.eye) {
    constexpr double kPi = 3.14159265358979323846;
    fwd = cam.target - cam.eye;
    if (!(fwd.norm() > 0)) fail("render: camera eye and target coincide");
    fwd.normalize();
    right = fwd.cross(cam.up);
    if (right.norm() < 1e-9) right = fwd.cross(Vec3(0, 0, -1));  // looking straight down
    right.normalize();
    up = right.cross(fwd);
    cx = 0.5 * w;
    cy = 0.5 * h;
    perspective = cam.fov_deg > 0;
    if (perspective) {
      focal = 0.5 * h / std::tan(0.5 * cam.fov_deg * kPi / 180.0);
    } else {
      if (!(cam.ortho_height > 0)) fail("render: ortho_height must be > 0");
      focal = h / cam.ortho_height;
    }
  }

  // Screen position and depth along fwd; false when behind a perspective camera.
  bool project(const Vec3& p, double& sx, double& sy, double& depth) const {
    const Vec3 d = p - eye;
    depth = d.dot(fwd);
    const double s = perspective ? (depth > 1e-9 ? focal / depth : -1) : focal;
    if (s <= 0) return false;
    sx = cx + s * d.dot(right);
    sy = cy - s * d.dot(up);
    return true;
  }

  double pixels_per_unit(double depth) const { return perspective ? focal / depth : focal; }

  // The ray through pixel position (px, py); dir has unit length.
  void ray(double px, double py, Vec3& origin, Vec3& dir) const {
    const double u = (px - cx) / focal, v = (cy - py) / focal;
    if (perspective) {
      origin = eye;
      dir = (fwd + u * right + v * up).normalized();
    } else {
      origin = eye + u * right + v * up;
      dir = fwd;
    }
  }

  // Depth along fwd of the point origin + t·dir of a ray from ray().
  double depth_of(const Vec3& origin, const Vec3& dir, double t) const {
    return (origin - eye).dot(fwd) + t * dir.dot(fwd);
  }
};

}  // namespace nsf
