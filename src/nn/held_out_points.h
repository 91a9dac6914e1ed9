#pragma once
// `nsf eval --held-out-particles K`: how well a basis model's fields read at points that are not
// particles (the ROM's --upsample, a host's query; nn/point_interpolation.h). Every K-th particle
// is held out, its fields are read from the other particles' through the interpolation, and both
// those and the model's own fields at the held-out particles are compared with the truth there.
#include <string>
#include <vector>

#include "core/types.h"
#include "nn/field_checks.h"
#include "nn/neural_fields.h"
#include "nn/point_interpolation.h"

namespace nsf {

struct HeldOutErrors {
  size_t particles = 0;
  // δ (eq. 11 over the held-out particles), relative τ and C errors: read from the others, and
  // the model's own at those particles.
  double delta = 0, stress = 0, affine = 0;
  double own_delta = 0, own_stress = 0, own_affine = 0;
};

class HeldOutPoints {
 public:
  // Throws nsf::Error for an MLP model (its fields are functions of X everywhere: there is
  // nothing to interpolate), a stride < 2, or an unknown scheme.
  HeldOutPoints(const NeuralFields& nf, size_t stride, const std::string& scheme, int neighbours);

  // One frame: the model's fields at every particle (xm, tm, cm, in particle order) against
  // the truth (x: positions, tau: 6|P| as stored, C: 9|P| row-major).
  void add_frame(const std::vector<Vec3>& xm, const std::vector<Mat3>& tm,
                 const std::vector<Mat3>& cm, const std::vector<Vec3>& x, const float* tau,
                 const float* C);
  // The sums so far as errors; start() clears them for the next run.
  HeldOutErrors errors() const;
  void start();

 private:
  std::vector<size_t> held_, others_;
  PointInterpolation weights_;  // held-out point → entries of others_
  std::vector<Vec3> X_;
  double ex_ = 0, nx_ = 0, own_ex_ = 0;
  ErrorSum stress_, affine_, own_stress_, own_affine_;
};

}  // namespace nsf
