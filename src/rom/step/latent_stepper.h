#pragma once
// The reduced-order simulator (§5): time-stepping in the latent space of a trained model. One
// step = (1) infer x, v, τ, C on the integration particles N, (2) one MPM step on N with the
// full-order engine's own transfers (G2P on the sample particles S only), (3) Gauss–Newton
// inversion of g on S for ẑ_{n+1}. No torch types; a host program embeds it through the
// embedding API (include/nsf/runtime.h, src/runtime/), which hides it and its Eigen types.
#include <memory>
#include <string>
#include <vector>

#include "core/timer.h"
#include "mpm/scene/scene.h"
#include "nn/neural_fields.h"
#include "rom/rom_options.h"

namespace nsf {

struct RigidFrames;

struct RomTimes {
  PhaseTimer inference;  // g on the candidates, τ and C on N
  PhaseTimer mpm;        // I, N, and the MPM step on N
  PhaseTimer inversion;  // Gauss–Newton
  PhaseTimer refresh;    // rebuilding the candidate set from g on all particles
};

// What a run has done so far, for reports and checks.
struct RomDiagnostics {
  RomTimes times;
  std::string field_sources;      // where x, τ and C come from ("x from g, tau from h, C from l")
  double mean_N = 0, mean_K = 0;  // mean |N| and candidates |K| over the steps so far
  size_t quadrature_points = 0;   // points that can join N (|P| unless thinned)
  long refreshes = 0;             // candidate sets rebuilt from all positions
  long integration_misses = -1;  // N missed (StepperChecks::verify_integration_set); −1: unchecked
  double last_residual = 0;      // rms ‖g − x‖ on S after the last inversion (m)
  // With QDEIM's samples (rom.sampling = "qdeim"): the condition number of the orthonormal
  // tangent basis of g restricted to S (rom/step/sample_selection.h); −1 otherwise.
  double sample_condition = -1;
  // How far ẑ_n is from the latents the model was trained on (the surface its training runs span
  // over μ and time; rom/inversion/latent_prior.h), in training spreads; −1 for a model that does
  // not store them. Far from it, h and l answer for states they never saw.
  double training_distance = -1;
  // Σ over steps of the samples' kinetic energy the inversion keeps, over Σ of what the MPM step
  // gave them: below 1, the projection onto g's tangent bleeds velocity every step.
  double energy_kept = 1;
  // The last step's Courant number on N: its fastest point's speed × Δt over Δx (cells a step).
  // Past 1 the explicit MPM step on N is unstable: a latent about to diverge shows here first.
  double courant = 0;
};

class LatentStepper {
 public:
  // `scene` must be the model's scene (same particles; checked) with μ already applied; `mu` is
  // passed to h when the model conditions on it. The initial latent ẑ_0 is the encoding of the
  // rest state refined on S; ẑ_{-1} fits X − Δt·v⁰ on S, so the first backward difference
  // reproduces the scene's initial velocities.
  LatentStepper(NeuralFields& fields, Scene scene, double mu, const RomOptions& options);
  ~LatentStepper();
  LatentStepper(const LatentStepper&) = delete;
  LatentStepper& operator=(const LatentStepper&) = delete;

  void step();
  void advance_frame();  // steps_per_frame() steps

  // The latent pair and the clock of the run: what a guard (rom/step/step_guard.h) keeps before a
  // step and puts back to redo it. The tracked state's own F and plastic state are not copied:
  // restoring any checkpoint puts them back as they were at the newest one
  // (TrackedParticles::rollback), since older states are not kept.
  struct Checkpoint {
    Latent z, z_prev;
    double t = 0;
    long n = 0;
  };
  Checkpoint checkpoint();
  void restore(const Checkpoint& c);
  // One step of Δt taken as `parts` steps of Δt/parts (the same clock and step count after), the
  // latent velocity kept: ẑ_{n−1} is moved to ẑ_n − (ẑ_n − ẑ_{n−1})/parts before and back to a full
  // step's distance after. A guard's recovery that keeps the run's momentum.
  void step_split(int parts);
  // What the last step tells of its own health, online: the inversion's rms misfit at S in
  // cells, the Courant number on N (RomDiagnostics::last_residual / Δx and ::courant), and the
  // cells left between N and the place where the engine's stencils no longer fit (1.5 Δx inside
  // a domain face; full order's walls keep its particles a cell or more short of it).
  struct Signals {
    double residual_cells = 0, courant = 0, grid_margin = 0;
  };
  Signals signals() const;

  double time() const;
  double dt() const;  // the ROM step
  int steps_per_frame() const;
  long step_count() const;
  // The model's latents ẑ_n and ẑ_{n−1} (without the rigid frames' entries, which a Checkpoint
  // holds too: RomOptions::rigid_frames).
  const Latent& latent() const;
  const Latent& previous_latent() const;
  // The Gauss–Newton options of the step's inversion (its latent prior included), for a fit of
  // the model's latent and the rigid frames' entries after it; valid while this stepper lives.
  const GaussNewtonOptions& inversion_options() const;
  // The rigid frames (RomOptions::rigid_frames; off where none), valid while this stepper lives.
  const RigidFrames& rigid_frames() const;

  // x = g(X, ẑ_n) and, if v is given, v = (g(X, ẑ_n) − g(X, ẑ_{n−1}))/Δt at prepared points
  // (fields.prepare(X): the scene's particles or any other rest positions, Fig. 6) of scene
  // objects `object` (one per point), each moved by its object's rigid frame if it has one.
  void state(const NeuralFields::Points& X, const std::vector<uint16_t>& object,
             std::vector<Vec3>& x, std::vector<Vec3>* v) const;
  // The same for all particles of the scene; also refreshes the candidate set for free.
  void particle_state(std::vector<Vec3>& x, std::vector<Vec3>* v);
  // τ and C of every particle at ẑ_n, from the sources the step itself uses (h or its
  // replacements, l or its), for output (a source's evaluate with for_step false).
  void particle_fields(std::vector<Mat3>& tau, std::vector<Mat3>& C);
  // τ alone, the same way (the embedding API's Runtime::stress).
  void particle_stress(std::vector<Mat3>& tau);
  // C alone, the same way (the embedding API's Runtime::affine).
  void particle_affine(std::vector<Mat3>& C);

  // The rigid frames' now: each particle's (−1: none; empty for a run without frames), and frame
  // f's map of g's positions y, x = R y + offset.
  std::vector<int> particle_rigid_frames() const;
  void rigid_frame_pose(int f, Mat3& R, Vec3& offset) const;

  size_t particle_count() const;
  size_t sample_count() const;  // |S| now
  const std::vector<uint32_t>& samples() const;
  // N of the last step; with a thinned quadrature, ids ≥ particle_count() are merged points.
  const std::vector<uint32_t>& integration_particles() const;
  RomDiagnostics diagnostics() const;
  // The scene's colliders, which the MPM step on N sets to its time: a host moves one between
  // steps with RigidCollider::drive.
  std::vector<std::unique_ptr<Collider>>& colliders();
  // The model's training box (data/training_box.h) and the cell size of the grid it steps on (the
  // scene's Δx × RomOptions::grid_factor).
  const TrainingBox& training_box() const;
  double grid_dx() const;

 private:
  friend void set_stepper_checks(LatentStepper&, const struct StepperChecks&);
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace nsf
