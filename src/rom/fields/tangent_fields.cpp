#include "rom/fields/sources.h"

#include <torch/torch.h>

#include "core/error.h"
#include "nn/latent_inversion.h"
#include "nn/model.h"
#include "rom/fields/network_fields.h"
#include "rom/linearized_field.h"

namespace nsf {

namespace {

// The expansion of one network over every point of the table; with the network itself beside
// it, for what must stay exact. The table must not change (no thinned quadrature).
struct Tangent {
  Tangent(const FieldContext& c, int64_t out_dim, LinearizedField::Network net,
          std::unique_ptr<PointFieldSource> exact_field = nullptr)
      : exact(std::move(exact_field)) {
    if (!(c.tangent_radius > 0))
      fail("rom: the tangent cache needs a positive anchor radius (--linearize), got ",
           c.tangent_radius);
    lin = std::make_unique<LinearizedField>(std::move(net), out_dim,
                                            normalised_points(c.fields.model(), c.points), c.spread,
                                            c.tangent_radius);
  }
  void evaluate(const std::vector<uint32_t>& ids, const Latent& z, const Latent& anchor_near,
                std::vector<double>& out) {
    lin->prepare(ids, anchor_near);
    lin->evaluate(ids, z, out);
  }
  std::unique_ptr<LinearizedField> lin;
  std::unique_ptr<PointFieldSource> exact;
};

[[noreturn]] void refuse_new_points() {
  fail(
      "rom: the tangent cache expands each particle's own fields and does not combine with a "
      "thinned quadrature (--quadrature)");
}

class TangentDeformation final : public DeformationSource {
 public:
  explicit TangentDeformation(const FieldContext& c)
      : exact_(make_network_deformation(c)),
        t_(c, 3, [m = &c.fields.model()](const torch::Tensor& Xn, const torch::Tensor& z) {
          return m->deform(Xn, z);
        }) {}
  std::string describe() const override { return "x from g's tangent cache"; }
  void set_points() override { refuse_new_points(); }
  bool exact() const override { return false; }
  void positions(const std::vector<uint32_t>& ids, const Latent& z, const Latent& now,
                 std::vector<Vec3>& x) override {
    std::vector<double> out;
    t_.evaluate(ids, z, now, out);
    x.resize(out.size() / 3);
    for (size_t k = 0; k < x.size(); ++k) x[k] = Vec3(out[3 * k], out[3 * k + 1], out[3 * k + 2]);
  }
  std::unique_ptr<SampleDeformation> samples(const std::vector<uint32_t>& S) override {
    return exact_->samples(S);  // the fit itself stays exact
  }
  long anchors() const override { return t_.lin->anchors(); }

 private:
  std::unique_ptr<DeformationSource> exact_;
  Tangent t_;
};

// τ (d = 6) or C (d = 9) through the expansion of h or l.
class TangentField final : public PointFieldSource {
 public:
  TangentField(const FieldContext& c, int64_t d, LinearizedField::Network net,
               std::unique_ptr<PointFieldSource> exact, std::string what)
      : d_(d), t_(c, d, std::move(net), std::move(exact)), what_(std::move(what)) {}
  std::string describe() const override { return what_; }
  void set_points() override { refuse_new_points(); }
  void evaluate(const std::vector<uint32_t>& ids, const LatentPair& s, bool for_step,
                std::vector<Mat3>& out) override {
    if (!for_step) return t_.exact->evaluate(ids, s, for_step, out);
    std::vector<double> v;
    t_.evaluate(ids, s.z, s.z, v);
    out.resize(ids.size());
    for (size_t k = 0; k < ids.size(); ++k) {
      const double* e = &v[size_t(d_) * k];
      if (d_ == 6)
        out[k] << e[0], e[3], e[5], e[3], e[1], e[4], e[5], e[4], e[2];
      else
        out[k] = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(e);
    }
  }

 private:
  int64_t d_;
  Tangent t_;
  std::string what_;
};

}  // namespace

std::unique_ptr<DeformationSource> make_tangent_deformation(const FieldContext& c) {
  return std::make_unique<TangentDeformation>(c);
}

std::unique_ptr<PointFieldSource> make_tangent_stress(const FieldContext& c) {
  const float mu = float(c.mu);
  return std::make_unique<TangentField>(
      c, 6,
      [m = &c.fields.model(), mu](const torch::Tensor& Xn, const torch::Tensor& z) {
        return m->stress(Xn, z, torch::full({Xn.size(0), 1}, mu));
      },
      make_network_stress(c), "tau from h's tangent cache");
}

std::unique_ptr<PointFieldSource> make_tangent_affine(const FieldContext& c) {
  return std::make_unique<TangentField>(
      c, 9,
      [m = &c.fields.model()](const torch::Tensor& Xn, const torch::Tensor& z) {
        return m->affine(Xn, z);
      },
      make_network_affine(c), "C from l's tangent cache");
}

}  // namespace nsf
