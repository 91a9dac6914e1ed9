#pragma once
// The built-in field sources (rom/fields/field_source.h), one file each;
// rom/fields/field_registry.cpp lists them under their names.
#include "rom/fields/field_source.h"

namespace nsf {

// The paper's coordinate networks g, h, l.
std::unique_ptr<DeformationSource> make_network_deformation(const FieldContext& context);
std::unique_ptr<PointFieldSource> make_network_stress(const FieldContext& context);
std::unique_ptr<PointFieldSource> make_network_affine(const FieldContext& context);
// A basis model's per-point bases times the latent's coefficients (nn/basis_decoders.h).
std::unique_ptr<DeformationSource> make_basis_deformation(const FieldContext& context);
std::unique_ptr<PointFieldSource> make_basis_stress(const FieldContext& context);
std::unique_ptr<PointFieldSource> make_basis_affine(const FieldContext& context);
// CROM's τ(∂g/∂X) through the material, with no plastic history.
std::unique_ptr<PointFieldSource> make_crom_stress(const FieldContext& context);
// C = 0.
std::unique_ptr<PointFieldSource> make_zero_affine(const FieldContext& context);
// Each particle's own F^E, plastic state and C, as full order keeps them
// (rom/step/tracked_particles.h).
std::unique_ptr<PointFieldSource> make_tracked_stress(const FieldContext& context);
std::unique_ptr<PointFieldSource> make_tracked_affine(const FieldContext& context);
// v on N: g's backward difference (the paper); each point's own G2P velocity of the step before.
std::unique_ptr<VelocitySource> make_latent_velocity(const FieldContext& context);
std::unique_ptr<VelocitySource> make_tracked_velocity(const FieldContext& context);

}  // namespace nsf
