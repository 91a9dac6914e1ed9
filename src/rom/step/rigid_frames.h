#pragma once
// Rigid frames over the latent manifold (issue #55 item 2; docs/ROM.md, "Rigid frames"): each
// listed scene object moves its decoded positions as a rigid body,
//   x = R_o (g(X, ẑ) − c_o) + c_o + t_o,   R_o = exp([θ_o]×),
// with c_o the object's mass-weighted rest centroid, and θ_o, t_o fitted beside ẑ. Of a throw or
// a spin that no training run made, the rigid part is then a motion the reduced step holds
// whatever the latent spans. The stepper's latent is ẑ followed by (θ_o, t_o) per framed object;
// the model's fields read ẑ alone, and τ, C from the model turn with the frame (R f Rᵀ).
#include <memory>
#include <vector>

#include "core/types.h"
#include "nn/neural_fields.h"
#include "rom/fields/field_source.h"

namespace nsf {

struct RigidFrames {
  int r = 0;                   // the model's latent dimension
  int frames = 0;              // framed objects; 0: none (the stepper's latent is the model's)
  std::vector<Vec3> pivot;     // c per frame
  std::vector<int> frame;      // per row of the point table: its frame, −1 for none
  std::vector<int> object_of;  // per frame: the scene object it moves

  bool on() const { return frames > 0; }
  int dim() const { return r + 6 * frames; }
  // The model's part of a stepper latent.
  Latent model(const Latent& z) const { return on() ? Latent(z.head(r)) : z; }
  // A model latent with every frame at rest.
  Latent augment(const Latent& z) const;
  Mat3 rotation(const Latent& z, int f) const;
  Vec3 translation(const Latent& z, int f) const { return z.segment<3>(r + 6 * f + 3); }
  // Frame f's map of g's positions y at z: x = R y + offset, offset = c + t − R c.
  void pose(const Latent& z, int f, Mat3& R, Vec3& offset) const;
  // The frame that moves scene object o (−1: none).
  int frame_of_object(int o) const;
  // g's positions x at rows `ids` of the point table (null: rows 0, 1, …) into the frames of z.
  void apply(const std::vector<uint32_t>* ids, const Latent& z, std::vector<Vec3>& x) const;
  // τ or C of the model at rows `ids` of the point table turned into the frames of z (R f Rᵀ).
  void turn(const std::vector<uint32_t>& ids, const Latent& z, std::vector<Mat3>& f) const;
  // The same for points of scene objects `object` (one per point), which need not be the
  // table's: points between the particles (--upsample).
  void apply_to_objects(const std::vector<uint16_t>& object, const Latent& z,
                        std::vector<Vec3>& x) const;
  // The point table's merged points, appended after its `particles` rows: the j-th takes the
  // frame of its group's particle member[j].
  void extend(size_t particles, const std::vector<uint32_t>& member);
};

// Frames for the scene objects `objects` (indices; throws nsf::Error for one the scene lacks):
// `object` per particle, `X` and `mass` its rest positions and masses.
RigidFrames make_rigid_frames(int r, const std::vector<int>& objects, const std::vector<Vec3>& X,
                              const std::vector<double>& mass, const std::vector<uint16_t>& object);

// g at rows `ids` of the point table (g's own samples) in the frames: its Jacobian holds ∂/∂ẑ,
// ∂/∂θ and ∂/∂t.
std::unique_ptr<SampleDeformation> in_rigid_frames(std::unique_ptr<SampleDeformation> g,
                                                   const RigidFrames& frames,
                                                   std::vector<uint32_t> ids);
// g in the frames; its samples' Jacobian holds ∂/∂ẑ, ∂/∂θ and ∂/∂t.
std::unique_ptr<DeformationSource> in_rigid_frames(std::unique_ptr<DeformationSource> g,
                                                   const RigidFrames& frames);
// τ or C at the model's latent, turned into each point's frame (R f Rᵀ) unless `rotate` is off
// (a tracked source, whose own state turned with the body).
std::unique_ptr<PointFieldSource> in_rigid_frames(std::unique_ptr<PointFieldSource> f,
                                                  const RigidFrames& frames, bool rotate);

}  // namespace nsf
