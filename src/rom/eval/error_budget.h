#pragma once
// Where a reduced-order run's error comes from (docs/ROM.md, "Error budget"), measured on the
// ground truth's own frames next to the run:
//   representation: each truth frame through the encoder, ẑ = e(xⁿ) refined on positions as
//                   training refines the latents h and l learn from (nn/latent_inversion.h,
//                   FrameLatentRefiner), then the decoders — the model's best without dynamics;
//   projection:     the truth's sample positions pushed through the ROM's inversion (the same
//                   samples and Gauss–Newton, warm-started frame to frame) — what the samples
//                   alone pin down of the state, τ and C included;
//   dynamics:       the rest, the run's own error beyond the projection.
// With rigid frames (rom/step/rigid_frames.h) both terms are of the framed model: the projection
// fits ẑ and the frames as the step does, and the representation is the better of the encoded ẑ
// and a fit of ẑ and the frames to every particle (from the encoded ẑ with the frames at rest, and
// from the last frame's fit), so that it stays a floor for the framed run.
#include <memory>
#include <vector>

#include "core/types.h"
#include "nn/field_checks.h"
#include "nn/neural_fields.h"
#include "rom/rom_options.h"

namespace nsf {

class SampleDeformation;
class FrameLatentRefiner;
struct RigidFrames;

// δ of eq. (11) and the relative errors of τ and C over the frames added so far; < 0 where the
// truth's field is zero (not measured).
struct FieldErrors {
  double delta = -1, stress = -1, affine = -1;
};

struct ErrorBudgetResult {
  FieldErrors encoded, projected;
  double projection_iterations = 0;  // mean Gauss–Newton iterations per frame
};

class ErrorBudget {
 public:
  // `fields` and the particles' rest positions X of the run's scene; `samples`: the ROM's sample
  // ids; `z0`: the ROM's initial latent, the model's part (the projection's first warm start);
  // `frames`: the run's rigid frames (null or off: none), which outlive the budget.
  ErrorBudget(NeuralFields& fields, const std::vector<Vec3>& X,
              const std::vector<uint32_t>& samples, double mu, const GaussNewtonOptions& inversion,
              const Latent& z0, const RigidFrames* frames = nullptr);
  ~ErrorBudget();

  // One truth frame (frames 1…N): positions, velocities (for a C that reads the latent
  // velocity), Kirchhoff stress and affine matrices per particle.
  void add_frame(const std::vector<Vec3>& x, const std::vector<Vec3>& v,
                 const std::vector<Mat3>& tau, const std::vector<Mat3>& C);
  ErrorBudgetResult result() const;

 private:
  struct Sums {
    ErrorSum x, stress, affine;
    FieldErrors errors() const;
  };
  void add(Sums& sums, const Latent& z, const std::vector<Vec3>& x, const std::vector<Vec3>& v,
           const std::vector<Mat3>& tau, const std::vector<Mat3>& C);
  // The framed representation's latent: ẑ and the frames fitted to every particle's x.
  Latent framed_fit(const Latent& encoded, const std::vector<Vec3>& x);

  NeuralFields& fields_;
  NeuralFields::Points points_;
  std::vector<uint32_t> samples_;
  double mu_;
  GaussNewtonOptions inversion_;
  std::unique_ptr<SampleDeformation> g_;
  std::unique_ptr<FrameLatentRefiner> refiner_;
  const RigidFrames* frames_;               // null: none
  std::unique_ptr<SampleDeformation> all_;  // framed g on every particle (frames only)
  std::vector<uint32_t> all_ids_;
  Latent z_, z_framed_;  // the projection's; the framed representation's
  Sums encoded_, projected_;
  long added_ = 0, iterations_ = 0;
  std::vector<Vec3> gx_, target_;
  std::vector<Mat3> tau_, C_;
};

}  // namespace nsf
