#pragma once
// The per-particle arrays of a run frame as every export format holds them, under one set of names
// (docs/VISUALISE.md): the run file's own names for what it stores (v, tau, F; docs/OUTPUT.md) and
// two derived ones (speed, von_mises). The VTU, legacy VTK, PLY and XDMF writers all take their
// arrays, names, layouts and order from here, so the formats cannot drift apart.
#include <cstdint>
#include <string>
#include <vector>

#include "io/run_reader.h"

namespace nsf {

// Names of the per-particle arrays, shared by the export formats and the run file's XDMF sidecar.
namespace field_name {
inline constexpr const char* kPosition = "x";  // the geometry; an array too where a reader needs it
inline constexpr const char* kVelocity = "v";
inline constexpr const char* kSpeed = "speed";
inline constexpr const char* kVonMises = "von_mises";
inline constexpr const char* kStress = "tau";
inline constexpr const char* kDeformation = "F";
inline constexpr const char* kAffine = "C";
inline constexpr const char* kRestPosition = "X";
inline constexpr const char* kMass = "mass";
inline constexpr const char* kVolume = "volume";
inline constexpr const char* kMaterial = "material";
inline constexpr const char* kObject = "object";
}  // namespace field_name

// One named array: `components` values per particle, particle after particle.
struct FrameField {
  const char* name = "";
  int components = 1;
  bool index = false;             // uint16 (material, object); otherwise float64
  std::vector<double> values;     // float64 fields
  std::vector<uint16_t> indices;  // index fields
};

// v (3), speed, von_mises, tau (6: xx yy zz xy yz xz, the run file's order, which is also VTK's
// order for a symmetric tensor), F (9, row-major), material, object; in this order. The values of
// v, tau and F are the run file's. Fails naming `what` when the arrays differ in length.
std::vector<FrameField> frame_fields(const RunFrame& f, const std::vector<uint16_t>& material,
                                     const std::vector<uint16_t>& object, const std::string& what);

}  // namespace nsf
