#pragma once
// What the sources that evaluate the paper's coordinate networks f(X, ẑ) share (network, CROM):
// the model's networks and the point table's rest positions, prepared for them.
#include <memory>

#include "nn/coordinate_networks.h"
#include "nn/neural_fields.h"
#include "rom/fields/field_source.h"

namespace nsf {

class NetworkPoints {
 public:
  // Throws nsf::Error when the model was loaded without its networks (no LibTorch).
  explicit NetworkPoints(const FieldContext& c);
  void set_points();  // after the table's points change
  const CoordinateNetworks& net() const { return *fields_.networks(); }
  const CoordinateNetworks::Points& points() const { return *X_; }

 private:
  const NeuralFields& fields_;
  const PointTable& points_;
  std::unique_ptr<CoordinateNetworks::Points> X_;
};

}  // namespace nsf
