// GCC 12 reports false -Wmaybe-uninitialized warnings from inside Eigen's AVX-512 kernels for
// dynamic-size products (in the intrinsics headers, not in this code).
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

#include "nn/field_checks.h"

#include <Eigen/QR>
#include <cmath>
#include <map>
#include <unordered_map>

#include "core/error.h"
#include "mpm/bspline.h"

namespace nsf {

void require_finite_fields(const Eigen::VectorXd& z, const std::vector<Vec3>& x,
                           const std::vector<Mat3>& tau, const std::vector<Mat3>& C,
                           const std::string& source, const std::string& where, size_t frame) {
  const char* what = !z.allFinite() ? "latent" : nullptr;
  for (size_t i = 0; !what && i < x.size(); ++i)
    what = !x[i].allFinite()                       ? "positions"
           : i < tau.size() && !tau[i].allFinite() ? "stress"
           : i < C.size() && !C[i].allFinite()     ? "affine field"
                                                   : nullptr;
  if (what)
    fail(source, " gives a NaN or infinite ", what, " on ", where, ", frame ", frame,
         " (a damaged model, or one far outside its training); no row is written");
}

Mat3 stored_stress(const float* s) {
  Mat3 t;
  t << s[0], s[3], s[5], s[3], s[1], s[4], s[5], s[4], s[2];
  return t;
}

Mat3 stored_affine(const float* c) {
  return Eigen::Map<const Eigen::Matrix<float, 3, 3, Eigen::RowMajor>>(c).cast<double>();
}

double ErrorSum::relative() const {
  return ref > 0 ? std::sqrt(err / ref) : NAN;
}

void add_grid_force_error(const std::vector<Vec3>& x, const std::vector<double>& volume,
                          const std::vector<Mat3>& tau, const std::vector<Mat3>& tau_ref,
                          const Vec3& domain_lo, double dx, ErrorSum& sum) {
  if (tau.size() != x.size() || tau_ref.size() != x.size() || volume.size() != x.size())
    fail("grid force error: ", x.size(), " positions but ", volume.size(), " volumes, ", tau.size(),
         " and ", tau_ref.size(), " stresses");
  const double inv_dx = 1.0 / dx, Dinv = apic_scale(inv_dx);
  // Sparse: only the nodes the particles touch. Key = packed node index (21 bits per axis).
  std::unordered_map<uint64_t, std::pair<Vec3, Vec3>> nodes;
  nodes.reserve(8 * x.size());
  for (size_t p = 0; p < x.size(); ++p) {
    const Stencil st = quadratic_stencil(x[p], domain_lo, inv_dx);
    const Mat3 a = -volume[p] * Dinv * tau[p], b = -volume[p] * Dinv * tau_ref[p];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        for (int k = 0; k < 3; ++k) {
          const double w = st.w[0][i] * st.w[1][j] * st.w[2][k];
          const Vec3 d((i - st.fx[0]) * dx, (j - st.fx[1]) * dx, (k - st.fx[2]) * dx);
          const uint64_t key = (uint64_t(uint32_t(st.base[0] + i) & 0x1FFFFF) << 42) |
                               (uint64_t(uint32_t(st.base[1] + j) & 0x1FFFFF) << 21) |
                               uint64_t(uint32_t(st.base[2] + k) & 0x1FFFFF);
          auto& f = nodes.try_emplace(key, Vec3::Zero(), Vec3::Zero()).first->second;
          f.first += w * (a * d), f.second += w * (b * d);
        }
  }
  for (const auto& [key, f] : nodes) {
    (void)key;
    sum.err += (f.first - f.second).squaredNorm();
    sum.ref += f.second.squaredNorm();
  }
}

struct SmoothFit::Group {
  std::vector<size_t> members;
  Eigen::MatrixXd basis;  // members × monomials
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr;
};

namespace {

// Monomials of total degree ≤ `degree` in the three coordinates of u.
Eigen::VectorXd monomials(const Vec3& u, int degree) {
  std::vector<double> m;
  for (int a = 0; a <= degree; ++a)
    for (int b = 0; a + b <= degree; ++b)
      for (int c = 0; a + b + c <= degree; ++c)
        m.push_back(std::pow(u[0], a) * std::pow(u[1], b) * std::pow(u[2], c));
  return Eigen::Map<Eigen::VectorXd>(m.data(), Eigen::Index(m.size()));
}

}  // namespace

SmoothFit::SmoothFit(const std::vector<Vec3>& X, const std::vector<uint16_t>& object, int degree) {
  if (object.size() != X.size())
    fail("smooth fit: ", X.size(), " rest positions but ", object.size(), " object ids");
  if (degree < 0) fail("smooth fit: degree must be >= 0, got ", degree);
  std::map<uint16_t, std::vector<size_t>> by_object;
  for (size_t p = 0; p < X.size(); ++p) by_object[object[p]].push_back(p);
  for (auto& [id, members] : by_object) {
    (void)id;
    // Coordinates scaled to [-1, 1] over the object's box keep the monomials well conditioned.
    Vec3 lo = X[members[0]], hi = lo;
    for (size_t p : members) lo = lo.cwiseMin(X[p]), hi = hi.cwiseMax(X[p]);
    const Vec3 c = 0.5 * (lo + hi), h = (0.5 * (hi - lo)).cwiseMax(1e-12);
    const Eigen::Index cols = monomials(Vec3::Zero(), degree).size();
    Eigen::MatrixXd B(Eigen::Index(members.size()), cols);
    for (size_t i = 0; i < members.size(); ++i)
      B.row(Eigen::Index(i)) = monomials((X[members[i]] - c).cwiseQuotient(h), degree).transpose();
    Group g;
    g.members = std::move(members);
    g.qr.compute(B);
    g.basis = std::move(B);
    groups_.push_back(std::move(g));
  }
}

SmoothFit::~SmoothFit() = default;
SmoothFit::SmoothFit(SmoothFit&&) noexcept = default;
SmoothFit& SmoothFit::operator=(SmoothFit&&) noexcept = default;

void SmoothFit::add_residual(const std::vector<Mat3>& field, ErrorSum& sum) const {
  for (const Group& g : groups_) {
    Eigen::MatrixXd Y(Eigen::Index(g.members.size()), 9);
    for (size_t i = 0; i < g.members.size(); ++i)
      Y.row(Eigen::Index(i)) =
          Eigen::Map<const Eigen::Matrix<double, 1, 9>>(field.at(g.members[i]).data());
    const Eigen::MatrixXd residual = Y - g.basis * g.qr.solve(Y);
    sum.err += residual.squaredNorm();
    sum.ref += Y.squaredNorm();
  }
}

}  // namespace nsf
