// The paper's coordinate networks g, h, l as field sources: evaluated by the model's networks
// (nn/coordinate_networks.h), which only a model loaded with LibTorch has.
#include "rom/fields/network_fields.h"
#include "core/error.h"
#include "nn/coordinate_networks.h"
#include "nn/latent_inversion.h"
#include "rom/fields/sources.h"

namespace nsf {

NetworkPoints::NetworkPoints(const FieldContext& c) : fields_(c.fields), points_(c.points) {
  if (!fields_.networks())
    fail(
        "rom: this source evaluates the paper's coordinate networks, which need LibTorch, and "
        "this model was loaded without it (the torch-free runtime runs basis models)");
  set_points();
}

void NetworkPoints::set_points() {
  X_ = net().prepare(points_.X);
}

namespace {

class NetworkDeformation final : public DeformationSource {
 public:
  explicit NetworkDeformation(const FieldContext& c) : net_(c) {}
  std::string describe() const override { return "x from g"; }
  void set_points() override { net_.set_points(); }

  void positions(const std::vector<uint32_t>& ids, const Latent& z, const Latent&,
                 std::vector<Vec3>& x) override {
    net_.net().deform(net_.points(), &ids, {&z}, x);
  }

  // Both latents in one batched call.
  void positions_pair(const std::vector<uint32_t>& ids, const LatentPair& s, std::vector<Vec3>& x,
                      std::vector<Vec3>& x_prev) override {
    std::vector<Vec3> both;
    net_.net().deform(net_.points(), &ids, {&s.z, &s.z_prev}, both);
    x.assign(both.begin(), both.begin() + long(ids.size()));
    x_prev.assign(both.begin() + long(ids.size()), both.end());
  }

  std::unique_ptr<SampleDeformation> samples(const std::vector<uint32_t>& S) override {
    return net_.net().samples(net_.points(), S);
  }

 private:
  NetworkPoints net_;
};

class NetworkStress final : public PointFieldSource {
 public:
  explicit NetworkStress(const FieldContext& c) : net_(c), mu_(c.mu) {}
  std::string describe() const override { return "tau from h"; }
  void set_points() override { net_.set_points(); }
  void evaluate(const std::vector<uint32_t>& ids, const LatentPair& s, bool,
                std::vector<Mat3>& tau) override {
    net_.net().stress(net_.points(), &ids, s.z, mu_, tau);
  }

 private:
  NetworkPoints net_;
  double mu_;
};

class NetworkAffine final : public PointFieldSource {
 public:
  explicit NetworkAffine(const FieldContext& c) : net_(c) {}
  std::string describe() const override { return "C from l"; }
  void set_points() override { net_.set_points(); }
  void evaluate(const std::vector<uint32_t>& ids, const LatentPair& s, bool,
                std::vector<Mat3>& C) override {
    net_.net().affine(net_.points(), &ids, s.z, C);
  }

 private:
  NetworkPoints net_;
};

}  // namespace

std::unique_ptr<DeformationSource> make_network_deformation(const FieldContext& c) {
  return std::make_unique<NetworkDeformation>(c);
}
std::unique_ptr<PointFieldSource> make_network_stress(const FieldContext& c) {
  return std::make_unique<NetworkStress>(c);
}
std::unique_ptr<PointFieldSource> make_network_affine(const FieldContext& c) {
  return std::make_unique<NetworkAffine>(c);
}

}  // namespace nsf
