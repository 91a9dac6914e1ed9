#pragma once
// The stress a training particle would carry if its deformation changed by ΔF from the recorded
// one, through the scene's own constitutive model: the targets of h at perturbed latents
// (`nsf train --stiffness-noise`, docs/TRAINING.md). h learned on the trajectories alone has no
// stiffness off them; these targets give it the material's.
#include <string>
#include <vector>

#include "core/types.h"
#include "mpm/scene/scene.h"

namespace nsf {

class Dataset;

class StressResponse {
 public:
  // Builds each training run's scene from the JSON it stored (its μ applied), so each particle
  // has its material and initial plastic parameters. Throws nsf::Error if a run stored no scene,
  // a scene's particles differ from the run's, or a material is not Hencky-elastic.
  explicit StressResponse(const Dataset& data);

  // τ of particle p of training run `run` after F^E → ΔF·F^E, given its recorded τ. F^E is
  // recovered from τ by inverting the Hencky law (an isotropic τ fixes F^E up to a rotation,
  // which τ(ΔF·F^E) does not depend on), and a point at yield keeps its current yield stress.
  Mat3 respond(size_t run, size_t p, const Mat3& tau, const Mat3& dF) const;

 private:
  std::vector<Scene> scenes_;
};

}  // namespace nsf
