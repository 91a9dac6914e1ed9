#include "io/frame_fields.h"

#include "core/error.h"
#include "io/colormap.h"
#include "io/run_format.h"

namespace nsf {

namespace {

template <typename T, typename Pack>
FrameField floats(const char* name, int width, const std::vector<T>& src, Pack pack) {
  FrameField out;
  out.name = name;
  out.components = width;
  out.values.resize(src.size() * static_cast<size_t>(width));
  for (size_t i = 0; i < src.size(); ++i) pack(src[i], out.values.data() + i * width);
  return out;
}

FrameField indices(const char* name, const std::vector<uint16_t>& src) {
  FrameField out;
  out.name = name;
  out.index = true;
  out.indices = src;
  return out;
}

}  // namespace

std::vector<FrameField> frame_fields(const RunFrame& f, const std::vector<uint16_t>& material,
                                     const std::vector<uint16_t>& object, const std::string& what) {
  const size_t n = f.x.size();
  if (f.v.size() != n || f.tau.size() != n || f.F.size() != n || material.size() != n ||
      object.size() != n)
    fail(what, ": frame arrays of different lengths");
  std::vector<FrameField> out;
  out.push_back(floats(field_name::kVelocity, 3, f.v, run_format::pack_vec));
  out.push_back(
      floats(field_name::kSpeed, 1, f.v, [](const Vec3& v, double* o) { *o = v.norm(); }));
  out.push_back(
      floats(field_name::kVonMises, 1, f.tau, [](const Mat3& t, double* o) { *o = von_mises(t); }));
  out.push_back(floats(field_name::kStress, 6, f.tau, run_format::pack_sym));
  out.push_back(floats(field_name::kDeformation, 9, f.F, run_format::pack_mat));
  out.push_back(indices(field_name::kMaterial, material));
  out.push_back(indices(field_name::kObject, object));
  return out;
}

}  // namespace nsf
