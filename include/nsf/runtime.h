#pragma once
// nsf's embedding API: runs a trained reduced-order model (a .nsf file) on its scene, frame by
// frame, inside a host program (a game engine, a VR client, a design tool). docs/EMBEDDING.md.
//
// The interface holds only standard C++ types: no Eigen, JSON or torch type crosses it, and the
// library keeps every other symbol to itself, so a host may be built with other compiler flags
// (-march, -O) than the library was. Errors throw std::runtime_error naming the problem.
#include <array>
#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#if defined(__GNUC__)
#define NSF_API __attribute__((visibility("default")))
#else
#define NSF_API
#endif

namespace nsf {

// The library's version, "MAJOR.MINOR.PATCH" (nsf_version() in the C API).
NSF_API const char* version();
// The instruction set this copy of the library was built for: "x86-64-v2" for the baseline copy,
// "x86-64-v3" for the one glibc's loader picks on a CPU with AVX2 and FMA (docs/EMBEDDING.md),
// "native" for a -DNSF_NATIVE=ON build (nsf_build_arch() in the C API).
NSF_API const char* build_arch();

// How a run is set up; every field may be left as it is.
struct RuntimeOptions {
  // The scene's sweep parameter μ (its "sweep" section says what it sets). Required when the
  // scene has one, refused when it has none.
  std::optional<double> mu;
  // Sample particles |S| of the latent fit; 0: the scene's "rom" section, else the default.
  int samples = 0;
  // Threads for the MPM step and the networks; 0: all cores.
  int threads = 0;
  // "a.b.c=value" overrides of the scene, as `nsf rom --set` takes them.
  std::vector<std::string> overrides;
  // The error indicator's limits (docs/EMBEDDING.md, "Error indicator"): the inversion's misfit at
  // the samples (cells), the Courant number of the step, and the cells left before the grid's
  // edge. A step past the first two, or one that would carry a point off the grid, is redone
  // (recover) instead of ending the run; false: a step past a limit is kept (flagged), one off
  // the grid throws.
  double indicator_misfit_cells = 0.5;
  double indicator_courant = 1.0;
  double indicator_grid_margin = 0.5;
  bool recover = true;
};

// How the run is doing, online (no truth needed): Runtime::health().
struct RuntimeHealth {
  double indicator = 0;       // the last step's: below 1 fine, 1 or more past a limit
  double misfit_cells = 0;    // the inversion's rms misfit at the samples, in cells
  double courant = 0;         // the fastest integration point's cells per step
  double grid_margin = 0;     // cells left before the grid's edge
  bool flagged = false;       // the last step's indicator was 1 or more, or it was redone
  long recoveries = 0;        // steps redone so far
  std::string last_recovery;  // what the last one did, when and why ("" for none)
  // A collider has left the model's training box (more than a cell beyond where its training runs
  // moved it, or faster): the latent space may not hold what follows.
  bool outside_training = false;  // in the last step
  long steps_outside = 0;         // steps so far
  std::string training_note;      // what lay outside, the first time ("" while nothing has)
};

// A rigid collider's pose in the world frame.
struct ColliderPose {
  std::array<double, 3> position{};                           // its reference point, m
  std::array<double, 9> rotation{1, 0, 0, 0, 1, 0, 0, 0, 1};  // body → world, row-major
  std::array<double, 3> velocity{};                           // of that point, m/s
  std::array<double, 3> angular_velocity{};                   // rad/s, about that point
};

// A scene object's motion as a rigid body, fitted to its particles now (docs/EMBEDDING.md,
// "The API"): where to attach a camera, a sound or a rigid proxy to a deforming body. A rest
// point X of the object sits near rotation · (X − rest_position) + position.
struct ObjectPose {
  std::array<double, 3> position{};                           // centre of mass now, m
  std::array<double, 9> rotation{1, 0, 0, 0, 1, 0, 0, 0, 1};  // rest → now, row-major
  std::array<double, 3> velocity{};                           // of the centre of mass, m/s
  std::array<double, 3> angular_velocity{};                   // rad/s, about the centre of mass
  std::array<double, 3> rest_position{};                      // centre of mass at rest, m
  // The particles' rms distance (m) from that rigid copy of the rest shape: how far the body is
  // deformed (0 for a rigid motion).
  double misfit = 0;
};

// The reduced-order simulator of one scene at one μ. Not copyable; movable.
class NSF_API Runtime {
 public:
  // Loads the model and the scene it was trained on (same particles; checked), applies μ and
  // the overrides, and sets up the latent stepper at the scene's initial state.
  Runtime(const std::string& model_path, const std::string& scene_path,
          const RuntimeOptions& options = {});
  ~Runtime();
  Runtime(Runtime&&) noexcept;
  Runtime& operator=(Runtime&&) noexcept;
  Runtime(const Runtime&) = delete;
  Runtime& operator=(const Runtime&) = delete;

  std::size_t particle_count() const;
  int frame_count() const;    // the scene's frames (the run may go on past them)
  double frame_time() const;  // seconds per frame
  int steps_per_frame() const;
  double time() const;  // simulated seconds so far

  void advance_frame();  // steps_per_frame() steps
  void step();           // one reduced-order step
  RuntimeHealth health() const;
  // What the set-up warned of, one line each: μ outside the model's training range, a scene
  // outside its training family (a value no training run's scene took; the run then reads the
  // scene's rom.unseen profile: docs/GENERALIZE.md), a --set a profile hides.
  std::vector<std::string> warnings() const;

  // Positions (x0 y0 z0 x1 …, metres) of every particle into out[0, 3·particle_count());
  // throws if `size` (in floats) is less.
  void positions(float* out, std::size_t size) const;
  std::vector<float> positions() const;
  // Velocities, the same way (m/s): the backward difference of the last step.
  void velocities(float* out, std::size_t size) const;
  // The Kirchhoff stress τ = Jσ (Pa) of every particle, 3×3 row-major (τ00 τ01 τ02 τ10 …, 9
  // floats per particle) into out[0, 9·particle_count()); throws if `size` is less. It comes from
  // the source the ROM step itself takes τ from (the model's decoder; the particles' own tracked
  // state with rom.fields.stress = "tracked", where a particle outside the integration set keeps
  // the τ of the last step it took part in), at the current latent.
  void stress(float* out, std::size_t size) const;
  // The affine velocity field C (1/s, APIC's: a particle's velocity varies as v + C·(y − x) about
  // it) of every particle, the same way: 3×3 row-major, 9 floats per particle, from the source the
  // ROM step takes C from (the model's decoder, the tracked state of rom.fields.affine =
  // "tracked", zero for "none"), at the current latent.
  void affine(float* out, std::size_t size) const;
  // The latent ẑ_n of the run now (what `nsf serve` streams): latent_dim() floats into out;
  // throws if `size` is less.
  std::size_t latent_dim() const;
  void latent(float* out, std::size_t size) const;

  // The scene's objects, in the order of its "objects" list, each fitted as a rigid body
  // (ObjectPose): the rotation is the best fit of its particles' positions to their rest
  // positions about the centres of mass (Kabsch), ω = I⁻¹L. The first call after a step decodes
  // every particle, as velocities() does; the others that step reuse it.
  std::size_t object_count() const;
  ObjectPose object_pose(std::size_t i) const;

  // The scene's colliders, in the order of its "colliders" list.
  std::size_t collider_count() const;
  std::string collider_type(std::size_t i) const;   // "box", "cylinder", "plane"
  ColliderPose collider_pose(std::size_t i) const;  // now
  // The host takes collider i over: it is at `pose` now and moves on with the pose's velocities
  // until the next call (its scripted motion is ignored from now on). Call it before each step
  // or frame; the velocities are what the material in contact feels.
  void set_collider_pose(std::size_t i, const ColliderPose& pose);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace nsf
