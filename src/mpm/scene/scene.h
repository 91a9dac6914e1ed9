#pragma once
// A scene: simulation settings, the particles built from its objects, their materials and the
// colliders. Loaded from JSON (docs/SCENES.md), with command-line overrides applied first.
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/types.h"
#include "mpm/colliders/collider.h"
#include "mpm/materials/material.h"
#include "mpm/particles.h"
#include "mpm/scene/camera_json.h"

namespace nsf {

// How particle velocity and affine momentum go to the grid (§3.3).
enum class Transfer { APIC, PIC, RPIC };

struct SimSettings {
  Vec3 domain_lo = Vec3::Zero();
  Vec3 domain_hi = Vec3::Ones();
  double dx = 1.0 / 64;
  double dt = 1e-4;         // time step
  int frames = 10;          // saved frames after the initial state
  int substeps = 1;         // time steps per saved frame
  int ppc = 2;              // particles per cell along each axis (ppc^3 per cell)
  double density = 1000.0;  // default density, kg/m^3 (an object may override it)
  Vec3 gravity = Vec3(0, -9.8, 0);
  Transfer transfer = Transfer::APIC;
  double cfl = 0.6;                      // dt must satisfy dt <= cfl * dx / wave_speed
  Contact wall_contact = Contact::Slip;  // the domain walls
  double wall_friction = 0.0;
  int wall_nodes = 3;  // grid nodes of each domain face that act as the wall
};

struct Scene {
  std::string name;
  SimSettings settings;
  Particles particles;
  std::vector<std::unique_ptr<Material>> materials;  // indexed by Particles::material
  std::vector<std::unique_ptr<Collider>> colliders;
  std::optional<SceneCamera> camera;  // for `nsf render`; the simulation ignores it
  nlohmann::json source;  // the scene as loaded, overrides applied (stored in output files)
};

// Applies "a.b.c=value" overrides to a scene JSON (see docs/SCENES.md for the path rules).
void apply_overrides(nlohmann::json& scene, const std::vector<std::string>& overrides);

// Validates what the engine reads and builds the scene. Throws nsf::Error naming the key and value
// at fault. The top-level keys are all checked, but the contents of "sweep" (data/sweep_spec.h),
// "rom" (rom/setup/rom_section.h) and "train" (nn/train_section.h) are left to their owners; the
// commands check those too when they load a scene (rom/setup/scene_file.h). Relative file paths in
// the scene (mesh shapes) resolve against base_dir, normally the scene file's directory; empty
// means the working directory.
Scene build_scene(const nlohmann::json& scene, const std::string& base_dir = "");

// Reads a file and applies overrides, without building (a sweep builds one scene per μ). A file
// with "extends": "base.json" is merged over that scene file (relative to its own directory; RFC
// 7386: objects key by key, any other value replaced, null removes), all but its name. Fills in
// "name" from the file name when the file has none. Throws nsf::Error naming the file.
nlohmann::json read_scene_json(const std::string& path,
                               const std::vector<std::string>& overrides = {});

// Reads a file, applies overrides, builds. Throws nsf::Error for a missing or malformed file.
Scene load_scene(const std::string& path, const std::vector<std::string>& overrides = {});

}  // namespace nsf
