#pragma once
// Yardsticks for the stress and affine errors of `nsf eval`. MPM's per-particle τ and C carry
// particle-scale noise that no smooth field h(X, ẑ) or l(X, ẑ) can reproduce, and that the dynamics
// largely average out in P2G. A relative error against the raw per-particle values therefore
// stays well above zero; these measures say how much of a field is smooth and what the dynamics
// see of the error.
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "core/types.h"

namespace nsf {

// A particle's τ as a run file stores it (xx yy zz xy yz xz) and its C (row-major 9), as 3×3.
Mat3 stored_stress(const float* s);
Mat3 stored_affine(const float* c);

// A row of results is made only of finite predictions: fields that are NaN or infinite on a frame
// (damaged weights under a matching checksum, or a latent far outside training) are an nsf::Error
// naming `source` (the model), `where` (the run) and the frame, not a row of "-" or of 1e30 %.
void require_finite_fields(const Eigen::VectorXd& z, const std::vector<Vec3>& x,
                           const std::vector<Mat3>& tau, const std::vector<Mat3>& C,
                           const std::string& source, const std::string& where, size_t frame);

// Accumulates Σ‖a − b‖² and Σ‖b‖² over many frames; relative() = √(err / ref), NaN when ref = 0.
// Over positions against the truth's, it is δ of eq. (11).
struct ErrorSum {
  double err = 0, ref = 0;
  void add(const Mat3& a, const Mat3& b) { err += (a - b).squaredNorm(), ref += b.squaredNorm(); }
  void add(const Vec3& a, const Vec3& b) { err += (a - b).squaredNorm(), ref += b.squaredNorm(); }
  void add(const ErrorSum& o) { err += o.err, ref += o.ref; }
  double relative() const;
};

// The stress forces on the grid nodes, f_i = −Σ_p V⁰_p τ_p ∇w_ip(x_p) with quadratic B-splines
// (the only way τ enters the MPM step), once from `tau` and once from `tau_ref`, both at the
// positions x. Adds Σ_i ‖f_i − f_i^ref‖² and Σ_i ‖f_i^ref‖² to `sum`.
void add_grid_force_error(const std::vector<Vec3>& x, const std::vector<double>& volume,
                          const std::vector<Mat3>& tau, const std::vector<Mat3>& tau_ref,
                          const Vec3& domain_lo, double dx, ErrorSum& sum);

// Least-squares fits of a frame's field over the reference positions X by one polynomial of total
// degree `degree` per object: the best any smooth per-frame field of that form can do. The basis
// depends on X only, so it is factored once and reused for every frame.
class SmoothFit {
 public:
  SmoothFit(const std::vector<Vec3>& X, const std::vector<uint16_t>& object, int degree);
  ~SmoothFit();
  SmoothFit(SmoothFit&&) noexcept;
  SmoothFit& operator=(SmoothFit&&) noexcept;
  // Adds the fit's residual Σ‖field − fit‖² and Σ‖field‖² (Frobenius) to `sum`.
  void add_residual(const std::vector<Mat3>& field, ErrorSum& sum) const;

 private:
  struct Group;
  std::vector<Group> groups_;
};

}  // namespace nsf
