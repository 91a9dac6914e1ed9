#pragma once
// The seam of the reduced-order step (§5): where the step takes g's positions on the candidates,
// the Kirchhoff stress τ and the APIC affine matrices C on the integration points N. Each source
// is an object behind one of two small interfaces, chosen once, by name, when the stepper is
// built (as materials are by their registry): the trained decoders (the paper's networks, or the
// per-point bases of a basis model), CROM's τ(∂g/∂X), C = 0, the particles' own tracked state; and
// the velocities P2G carries (g's backward difference, or each point's own). A new source is one
// file in src/rom/fields/ plus a line in rom/fields/field_registry.cpp.
#include <Eigen/Core>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/types.h"
#include "mpm/material_point.h"
#include "nn/neural_fields.h"

namespace nsf {

class Material;
class SampleDeformation;
struct Particles;
class TrackedParticles;

// Every point that can join N, numbered as the stepper numbers them: the scene's particles
// (ids < particles), then the merged points of a thinned quadrature (rom/step/quadrature.h). The
// merged points change when the sample set does, and sources are told (set_points).
struct PointTable {
  size_t particles = 0;  // |P|
  std::vector<Vec3> X;   // rest positions
  std::vector<uint16_t> material;
  std::vector<MaterialPoint> mat0;  // the initial plastic state
  // Per merged point j (id particles + j): the particles it stands for, and their masses'
  // shares (summing to 1). Fields that live on particles (a basis) are averaged over them.
  std::vector<std::vector<std::pair<uint32_t, double>>> merged_members;
};

// What a source may read of the run; fixed for the stepper's life.
struct FieldContext {
  NeuralFields& fields;
  const PointTable& points;
  const std::vector<std::unique_ptr<Material>>& materials;
  double mu = 0;                        // the run's parameter (h's input when the model takes it)
  double dt = 0;                        // the ROM step (a split step shortens it)
  TrackedParticles* tracked = nullptr;  // the particles' own state, for the tracked sources
};

// The latent now and one step before: what a step's fields are functions of.
struct LatentPair {
  const Latent& z;       // ẑ_n
  const Latent& z_prev;  // ẑ_{n−1}
};

// g: positions x = g(X, ẑ) at rows of the point table, and the sample fit of the inversion.
class DeformationSource {
 public:
  virtual ~DeformationSource() = default;
  virtual std::string describe() const = 0;
  virtual void set_points() {}  // the point table changed
  // g at rows `ids` for the latent z; `now` is ẑ_n, about which an approximation may expand.
  virtual void positions(const std::vector<uint32_t>& ids, const Latent& z, const Latent& now,
                         std::vector<Vec3>& x) = 0;
  // g at rows `ids` for ẑ_n and ẑ_{n−1}, in one batched evaluation where the source can.
  virtual void positions_pair(const std::vector<uint32_t>& ids, const LatentPair& s,
                              std::vector<Vec3>& x, std::vector<Vec3>& x_prev) {
    positions(ids, s.z, s.z, x);
    positions(ids, s.z_prev, s.z, x_prev);
  }
  // The exact g and ∂g/∂ẑ at the sample particles `S`, for Gauss–Newton (nn/latent_inversion.h).
  virtual std::unique_ptr<SampleDeformation> samples(const std::vector<uint32_t>& S) = 0;
  // True when positions() is g itself, so that positions g gave elsewhere at the same latent
  // (the candidate refresh's) can stand in for it; false for an approximation.
  virtual bool exact() const { return true; }
};

// τ or C: 3×3 per point at rows of the point table.
class PointFieldSource {
 public:
  virtual ~PointFieldSource() = default;
  virtual std::string describe() const = 0;  // "tau from h", "C = 0", …
  virtual void set_points() {}
  // Values at rows `ids` at the state s. `for_step` false: for output, where an approximation
  // made for speed gives way to the field it approximates.
  virtual void evaluate(const std::vector<uint32_t>& ids, const LatentPair& s, bool for_step,
                        std::vector<Mat3>& out) = 0;
};

// v: the velocities on N that the step's P2G carries (the paper: g's backward difference).
class VelocitySource {
 public:
  virtual ~VelocitySource() = default;
  // Appended to the step's field sources ("v from …"); empty for the paper's backward difference.
  virtual std::string describe() const = 0;
  // Velocities at rows `ids`, whose positions are x = g(X, ẑ_n) and x_prev = g(X, ẑ_{n−1}).
  virtual void evaluate(const std::vector<uint32_t>& ids, const std::vector<Vec3>& x,
                        const std::vector<Vec3>& x_prev, std::vector<Vec3>& v) = 0;
};

using DeformationFactory = std::function<std::unique_ptr<DeformationSource>(const FieldContext&)>;
using PointFieldFactory = std::function<std::unique_ptr<PointFieldSource>(const FieldContext&)>;
using VelocityFactory = std::function<std::unique_ptr<VelocitySource>(const FieldContext&)>;

// The registries (rom/fields/field_registry.cpp). `make_*` throw nsf::Error naming the known
// sources for an unknown name.
enum class FieldRole { stress, affine };
void register_deformation_source(const std::string& name, DeformationFactory factory);
void register_point_field_source(FieldRole role, const std::string& name,
                                 PointFieldFactory factory);
void register_velocity_source(const std::string& name, VelocityFactory factory);
std::unique_ptr<DeformationSource> make_deformation_source(const std::string& name,
                                                           const FieldContext& context);
std::unique_ptr<PointFieldSource> make_point_field_source(FieldRole role, const std::string& name,
                                                          const FieldContext& context);
std::unique_ptr<VelocitySource> make_velocity_source(const std::string& name,
                                                     const FieldContext& context);
std::vector<std::string> deformation_source_names();
std::vector<std::string> point_field_source_names(FieldRole role);
std::vector<std::string> velocity_source_names();
// The record (a file under docs/experiments/) of a source that lost and was removed, by its role
// ("deformation", "stress", "affine", "velocity") and name; "" for any other. The registries
// refuse it naming the record, and so do a scene's rom.fields and `nsf rom`'s options.
std::string retired_field_source(const std::string& role, const std::string& name);

}  // namespace nsf
