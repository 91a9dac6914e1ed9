#pragma once
// Structure-of-arrays particle state. Index p is stable for the whole run (output files,
// the reduced-order model and tests refer to particles by it).
#include <cstdint>
#include <vector>

#include "core/types.h"
#include "mpm/material_point.h"

namespace nsf {

struct Particles {
  std::vector<Vec3> X;    // reference (rest) position
  std::vector<Vec3> x;    // current position
  std::vector<Vec3> v;    // velocity
  std::vector<Mat3> C;    // affine velocity field (APIC); velocity-gradient estimate in any scheme
  std::vector<Mat3> F;    // elastic deformation gradient F^E
  std::vector<Mat3> tau;  // Kirchhoff stress τ(F^E), computed after the return map
  std::vector<double> mass;
  std::vector<double> vol0;  // initial volume V_p^0
  std::vector<MaterialPoint> mat;
  std::vector<uint16_t> material;  // index into Simulation::materials
  std::vector<uint16_t> object;    // which scene object the particle came from (for colouring)

  size_t size() const { return x.size(); }

  // Appends one particle at rest position X with identity F and zero stress.
  void add(const Vec3& X0, const Vec3& v0, double m, double V0, const MaterialPoint& mp,
           uint16_t material_index, uint16_t object_index) {
    X.push_back(X0);
    x.push_back(X0);
    v.push_back(v0);
    C.push_back(Mat3::Zero());
    F.push_back(Mat3::Identity());
    tau.push_back(Mat3::Zero());
    mass.push_back(m);
    vol0.push_back(V0);
    mat.push_back(mp);
    material.push_back(material_index);
    object.push_back(object_index);
  }
};

}  // namespace nsf
