// A basis model's decoders as field sources (nn/basis_decoders.h): per point, the field is its
// mean plus its modes times coefficients that the latent gives once per step. A merged point of
// a thinned quadrature stands for its group, so its rows are the group's mass-weighted blend.
#include "core/error.h"
#include "nn/basis_decoders.h"
#include "nn/latent_inversion.h"
#include "rom/fields/sources.h"

namespace nsf {

namespace {

// Below this many points a parallel loop costs more than it saves.
constexpr int64_t kParallelPoints = 512;

const BasisDecoders& bases_of(const FieldContext& c) {
  if (!c.fields.bases())
    fail(
        "rom: the basis field sources need a model with per-point bases (nsf train --decoder "
        "basis); this model holds the paper's coordinate networks: use the network sources");
  return *c.fields.bases();
}

// One field's rows over the point table: the particles' own, then the merged points' blends.
class BasisRows {
 public:
  BasisRows(const PointBasis& basis, const PointTable& points) : b_(basis), points_(points) {
    set_points();
  }
  void set_points() {
    mean_.clear(), modes_.clear();
    for (const auto& members : points_.merged_members) b_.blend(members, mean_, modes_);
  }
  const PointBasis& basis() const { return b_; }
  // dim values of point `id` for coefficients c.
  void value(uint32_t id, const Eigen::VectorXf& c, float* out) const {
    if (id < b_.points) return b_.value(id, c, out);
    const size_t j = id - b_.points, d = size_t(b_.dim);
    b_.value_of(&mean_[j * d], &modes_[j * d * size_t(b_.K)], c, out);
  }

 private:
  const PointBasis& b_;
  const PointTable& points_;
  std::vector<float> mean_, modes_;
};

class BasisDeformation final : public DeformationSource {
 public:
  explicit BasisDeformation(const FieldContext& c)
      : c_(c), bases_(bases_of(c)), rows_(bases_.u, c.points) {}
  std::string describe() const override { return "x from g's basis"; }
  void set_points() override { rows_.set_points(); }
  void positions(const std::vector<uint32_t>& ids, const Latent& z, const Latent&,
                 std::vector<Vec3>& x) override {
    const Eigen::VectorXf c = bases_.deformation_coefficients(z);
    x.resize(ids.size());
    const int64_t n = int64_t(ids.size());
    // Each point on its own: any thread count gives the same bits.
#pragma omp parallel for schedule(static) if (n > kParallelPoints)
    for (int64_t k = 0; k < n; ++k) {
      float d[3];
      rows_.value(ids[k], c, d);
      x[k] = c_.points.X[ids[k]] + Vec3(d[0], d[1], d[2]);
    }
  }
  std::unique_ptr<SampleDeformation> samples(const std::vector<uint32_t>& S) override {
    return c_.fields.sample_deformation(c_.points.X, S);
  }

 private:
  const FieldContext& c_;
  const BasisDecoders& bases_;
  BasisRows rows_;
};

// τ (6 values, xx yy zz xy yz xz) or C (9, row-major).
class BasisField final : public PointFieldSource {
 public:
  BasisField(const FieldContext& c, bool stress)
      : c_(c),
        bases_(bases_of(c)),
        stress_(stress),
        rows_(stress ? bases_.tau : bases_.C, c.points) {}
  std::string describe() const override {
    return stress_ ? "tau from h's basis" : "C from l's basis";
  }
  void set_points() override { rows_.set_points(); }
  void evaluate(const std::vector<uint32_t>& ids, const LatentPair& s, bool,
                std::vector<Mat3>& out) override {
    // τ or C of a model that reads the latent velocity: ż as the step's backward difference.
    Eigen::VectorXd zdot;
    if (stress_ ? bases_.stress_uses_velocity : bases_.affine_uses_velocity)
      zdot = (s.z - s.z_prev) / c_.dt;
    const Eigen::VectorXf c = stress_ ? bases_.stress_coefficients(s.z, c_.mu, &zdot)
                                      : bases_.affine_coefficients(s.z, c_.mu, &zdot);
    out.resize(ids.size());
    const int64_t n = int64_t(ids.size());
#pragma omp parallel for schedule(static) if (n > kParallelPoints)
    for (int64_t k = 0; k < n; ++k) {
      float v[9];
      rows_.value(ids[k], c, v);
      if (stress_)
        out[k] << v[0], v[3], v[5], v[3], v[1], v[4], v[5], v[4], v[2];
      else
        out[k] << v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], v[8];
    }
  }

 private:
  const FieldContext& c_;
  const BasisDecoders& bases_;
  bool stress_;
  BasisRows rows_;
};

}  // namespace

std::unique_ptr<DeformationSource> make_basis_deformation(const FieldContext& c) {
  return std::make_unique<BasisDeformation>(c);
}
std::unique_ptr<PointFieldSource> make_basis_stress(const FieldContext& c) {
  return std::make_unique<BasisField>(c, true);
}
std::unique_ptr<PointFieldSource> make_basis_affine(const FieldContext& c) {
  return std::make_unique<BasisField>(c, false);
}

}  // namespace nsf
