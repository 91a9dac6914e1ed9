#pragma once
// Fields that live on the particles (a basis model's modes), read at other rest positions: the
// ROM's output points of Fig. 6 (`nsf rom --upsample`) and any point a host asks for. Each point
// becomes a short list of particles and weights, f(X) = Σ w_i f_i, computed once.
// Two schemes:
//   nearest: the nearest particle's value;
//   mls: moving least squares, linear, with a cubic-spline weight over the k nearest particles
//        (the support reaches just past the k-th):
//        exact for fields affine in X, and the weights still sum to 1.
#include <cstdint>
#include <string>
#include <vector>

#include "core/types.h"

namespace nsf {

struct PointInterpolation {
  std::vector<uint32_t> start;  // point i uses entries [start[i], start[i + 1])
  std::vector<uint32_t> particle;
  std::vector<float> weight;
  size_t size() const { return start.empty() ? 0 : start.size() - 1; }
};

// Interpolation support: measured at held-out particles (`nsf eval --held-out-particles`), 8
// neighbours read a basis model's stress between particles at half the error of 16 on
// metal_small (6.7 % against 13.9 %; the model at the particles: 4.9 %), positions alike
// (docs/experiments/2026-11-26-held-out-particles.md).
constexpr int kInterpolationNeighbours = 8;

// A point that coincides with a particle (within 1e-9 of the particles' extent) gets that
// particle alone, whatever the scheme. Throws nsf::Error for an unknown scheme or no particles.
PointInterpolation interpolate_points(const std::vector<Vec3>& particles,
                                      const std::vector<Vec3>& points,
                                      const std::string& scheme = "mls",
                                      int neighbours = kInterpolationNeighbours);

}  // namespace nsf
