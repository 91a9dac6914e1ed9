#include "io/colormap.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace nsf {

namespace {

Color hex(uint32_t rgb) {
  return Color(((rgb >> 16) & 0xff) / 255.0f, ((rgb >> 8) & 0xff) / 255.0f, (rgb & 0xff) / 255.0f);
}

constexpr std::array<uint32_t, 10> kTableau = {0x4e79a7, 0xf28e2b, 0xe15759, 0x76b7b2, 0x59a14f,
                                               0xedc948, 0xb07aa1, 0xff9da7, 0x9c755f, 0xbab0ac};
// matplotlib's viridis sampled at ten evenly spaced points; linear in between is close enough
// for pictures.
constexpr std::array<uint32_t, 10> kViridis = {0x440154, 0x482878, 0x3e4989, 0x31688e, 0x26828e,
                                               0x1f9e89, 0x35b779, 0x6ece58, 0xb5de2b, 0xfde725};

}  // namespace

Color palette(size_t index) {
  return hex(kTableau[index % kTableau.size()]);
}

Color viridis(double t) {
  if (!(t > 0)) t = 0;  // also catches NaN
  if (t > 1) t = 1;
  const double s = t * (kViridis.size() - 1);
  const size_t i = std::min(static_cast<size_t>(s), kViridis.size() - 2);
  const float f = static_cast<float>(s - i);
  return (1 - f) * hex(kViridis[i]) + f * hex(kViridis[i + 1]);
}

std::vector<Color> colors_by_index(const std::vector<uint16_t>& index) {
  std::vector<Color> out(index.size());
  for (size_t i = 0; i < index.size(); ++i) out[i] = palette(index[i]);
  return out;
}

std::vector<Color> colors_by_scalar(const std::vector<double>& value, double lo, double hi) {
  if (!(lo < hi)) {
    lo = std::numeric_limits<double>::infinity();
    hi = -lo;
    for (double s : value)
      if (std::isfinite(s)) {
        lo = std::min(lo, s);
        hi = std::max(hi, s);
      }
  }
  const double span = hi > lo ? hi - lo : 1.0;  // a constant field maps to the low end
  std::vector<Color> out(value.size());
  for (size_t i = 0; i < value.size(); ++i) {
    out[i] = std::isnan(value[i]) ? Color(0.5f, 0.5f, 0.5f) : viridis((value[i] - lo) / span);
  }
  return out;
}

std::vector<double> speeds(const std::vector<Vec3>& v) {
  std::vector<double> out(v.size());
  for (size_t i = 0; i < v.size(); ++i) out[i] = v[i].norm();
  return out;
}

double von_mises(const Mat3& tau) {
  const Mat3 s = tau - tau.trace() / 3.0 * Mat3::Identity();
  return std::sqrt(1.5 * s.squaredNorm());
}

std::vector<double> von_mises(const std::vector<Mat3>& tau) {
  std::vector<double> out(tau.size());
  for (size_t i = 0; i < tau.size(); ++i) out[i] = von_mises(tau[i]);
  return out;
}

}  // namespace nsf
