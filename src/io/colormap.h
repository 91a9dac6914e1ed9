#pragma once
// Particle colours for pictures: a categorical palette for object/material indices and a
// viridis-like map for scalars (speed, von Mises stress). Viridis because it stays readable in
// grey scale and for colour-blind viewers, and its brightness rises monotonically with the value.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "core/types.h"

namespace nsf {

using Color = Eigen::Vector3f;  // sRGB components in [0, 1]

Color palette(size_t index);  // Tableau-10 colours, repeating
Color viridis(double t);      // t clamped to [0, 1]

std::vector<Color> colors_by_index(const std::vector<uint16_t>& index);
// Maps [lo, hi] onto viridis. With lo >= hi the range is the data's own min/max; pass a fixed
// range for an animation so colours mean the same in every frame. NaN becomes grey.
std::vector<Color> colors_by_scalar(const std::vector<double>& value, double lo = 0, double hi = 0);

// Scalars worth colouring by.
std::vector<double> speeds(const std::vector<Vec3>& v);
// sqrt(3/2 s:s) with s the deviatoric part of τ: the yield measure of the von Mises models.
double von_mises(const Mat3& tau);
std::vector<double> von_mises(const std::vector<Mat3>& tau);

}  // namespace nsf
