#pragma once
// A reduced-order run watched for the start of a divergence, and brought back from one, so that
// a host never sees a diverged ROM end its session (issue #55 item 5; docs/EMBEDDING.md, "Error
// indicator"). After each step two online quantities are read, neither of which needs a truth:
//   the inversion's rms misfit at the samples, in cells: how far the latent space falls short
//     of the motion the MPM step gave the samples (LatentStepper's last_residual / Δx);
//   the Courant number on N: its fastest point's cells per step, past 1 an unstable step;
//   the grid margin: cells left between N and where the engine's stencils stop fitting (full
//     order's walls keep particles a cell or more short of it; a latent that carries a point
//     there is about to put it off the grid).
// The indicator is the largest of the first two over their limits and the margin's limit over
// the margin: at or past 1 the step is flagged. A step is redone when it throws RomDiverged (a
// point left the grid, a fit that is not finite) or its misfit or Courant number passes its
// limit (a margin alone only warns: the pose is the last step's, and resting there keeps it
// inside): from the state before it (the tracked state too) as two, then four, shorter steps that
// keep the latent velocity; else with the latent velocity set to zero (the run loses its momentum
// there and keeps its pose), else at rest from the pose a step earlier, else from the scene's
// initial pose at rest, always at the same time. Each recovery is counted and described.
// Apart from the indicator, each step checks the colliders against the model's training box
// (data/training_box.h): a collider more than a cell outside where the training runs moved it, or
// faster than they moved it, marks the run as outside the training box; the step goes on.
#include <string>

#include "rom/step/latent_stepper.h"

namespace nsf {

struct GuardOptions {
  double residual_cells = 0.5;  // the misfit at S that flags a step (cells)
  double courant = 1.0;         // the Courant number on N that flags a step
  double grid_margin = 0.5;     // the cells left before the grid's edge that flag a step
  bool recover = true;          // redo a flagged step; false: only report it
};

struct RomHealth {
  double indicator = 0;           // of the last step kept (≥ 1: past a limit)
  double residual_cells = 0;      // its misfit at S, in cells
  double courant = 0;             // its Courant number on N
  double grid_margin = 0;         // its cells left before the grid's edge
  bool flagged = false;           // the last step's indicator was 1 or more, or it was redone
  long recoveries = 0;            // steps redone so far
  std::string last_recovery;      // what the last one did, when and why; "" for none
  bool outside_training = false;  // the last step's colliders left the model's training box
  long steps_outside = 0;         // steps so far that did
  std::string training_note;      // what lay outside, the first time; "" while none has
};

// What lies outside the model's training box among `rom`'s colliders now, with the step and time
// ("" for nothing): a collider more than a cell beyond where the training runs moved it, or more
// than 10 % faster (data/training_box.h).
std::string outside_training_box(LatentStepper& rom);

class StepGuard {
 public:
  // Keeps `rom`'s state now as the initial state a last-resort recovery returns to.
  StepGuard(LatentStepper& rom, const GuardOptions& options = {});

  // One step of the ROM, redone as above when flagged. With recover off, RomDiverged reaches
  // the caller as the stepper throws it.
  void step();
  void advance_frame();  // steps_per_frame() steps

  const RomHealth& health() const { return health_; }

 private:
  // The last step's indicator from the stepper's diagnostics.
  double indicator();
  void step_or_recover();
  // The colliders against the training box, after a step.
  void check_training_box();
  // Runs one step from the stepper's state; true when it is kept (no RomDiverged, misfit and
  // Courant number within their limits), else `why` says what went wrong.
  // `parts` > 1 takes it as that many shorter steps (LatentStepper::step_split).
  bool attempt(std::string& why, int parts = 1);

  LatentStepper& rom_;
  GuardOptions options_;
  LatentStepper::Checkpoint initial_;
  LatentStepper::Checkpoint previous_;  // before the last step kept
  RomHealth health_;
};

}  // namespace nsf
