#include "rom/step/step_guard.h"

#include <algorithm>
#include <cstdio>
#include <string>

#include "core/error.h"
#include "mpm/colliders/rigid_collider.h"
#include "rom/step/rom_diverged.h"

namespace nsf {

StepGuard::StepGuard(LatentStepper& rom, const GuardOptions& options)
    : rom_(rom), options_(options), initial_(rom.checkpoint()), previous_(initial_) {
  if (!(options.residual_cells > 0) || !(options.courant > 0) || !(options.grid_margin > 0))
    fail("rom: the error indicator's limits must be positive numbers, got a misfit of ",
         options.residual_cells, " cells, a Courant number of ", options.courant,
         " and a grid margin of ", options.grid_margin, " cells");
}

double StepGuard::indicator() {
  const LatentStepper::Signals s = rom_.signals();
  health_.residual_cells = s.residual_cells;
  health_.courant = s.courant;
  health_.grid_margin = s.grid_margin;
  health_.indicator =
      std::max({s.residual_cells / options_.residual_cells, s.courant / options_.courant,
                options_.grid_margin / std::max(s.grid_margin, 1e-12)});
  return health_.indicator;
}

std::string outside_training_box(LatentStepper& rom) {
  const TrainingBox& box = rom.training_box();
  auto& colliders = rom.colliders();
  for (size_t i = 0; i < colliders.size() && !box.colliders.empty(); ++i) {
    const auto* rigid = dynamic_cast<const RigidCollider*>(colliders[i].get());
    if (!rigid) continue;
    const RigidPose& p = rigid->pose();
    const std::string why = box.collider_outside(i, p.center, p.velocity.norm(), rom.grid_dx());
    if (why.empty()) continue;
    char when[80];
    std::snprintf(when, sizeof when, "step %ld (t = %.4g s): ", rom.step_count(), rom.time());
    return when + why;
  }
  return "";
}

void StepGuard::check_training_box() {
  const std::string note = outside_training_box(rom_);
  health_.outside_training = !note.empty();
  if (!health_.outside_training) return;
  ++health_.steps_outside;
  if (health_.training_note.empty()) health_.training_note = note;
}

bool StepGuard::attempt(std::string& why, int parts) {
  try {
    if (parts == 1)
      rom_.step();
    else
      rom_.step_split(parts);
  } catch (const RomDiverged& e) {
    if (!options_.recover) throw;
    why = e.what();
    return false;
  }
  indicator();
  if (health_.residual_cells < options_.residual_cells && health_.courant < options_.courant)
    return true;
  char line[200];
  std::snprintf(line, sizeof line,
                "the error indicator reached %.3g (misfit at the samples %.3g cells, Courant "
                "number %.3g, %.3g cells from the grid's edge)",
                health_.indicator, health_.residual_cells, health_.courant, health_.grid_margin);
  why = line;
  return false;
}

void StepGuard::step() {
  step_or_recover();
  check_training_box();
}

void StepGuard::step_or_recover() {
  const LatentStepper::Checkpoint before = rom_.checkpoint();
  std::string why, again;
  if (attempt(why)) {
    health_.flagged = health_.indicator >= 1;
    previous_ = before;
    return;
  }
  health_.flagged = true;
  if (!options_.recover) return;  // flagged, kept: the caller decides
  ++health_.recoveries;
  char when[96];
  std::snprintf(when, sizeof when, "step %ld (t = %.4g s): ", before.n, before.t);
  // The same step in shorter parts, with its momentum: a step past the Courant limit, or one
  // whose motion g could not follow, is most often one taken too long.
  for (int parts : {2, 4}) {
    rom_.restore(before);
    if (attempt(again, parts)) {
      health_.last_recovery =
          when + why + "; redone as " + std::to_string(parts) + " shorter steps, momentum kept";
      return;
    }
  }
  LatentStepper::Checkpoint still = before;  // the same pose, at rest
  still.z_prev = still.z;
  rom_.restore(still);
  if (attempt(again)) {
    health_.last_recovery = when + why + "; redone with the latent velocity set to zero";
    return;
  }
  // The pose a step earlier, at rest, now: the last step may have put a point where no step
  // from its pose can go on (off the grid). The tracked state goes back to before the step (an
  // older one is not kept).
  LatentStepper::Checkpoint earlier = previous_;
  earlier.z_prev = earlier.z;
  earlier.t = before.t, earlier.n = before.n;
  rom_.restore(earlier);
  if (attempt(again)) {
    health_.last_recovery = when + why + "; redone at rest from the pose a step earlier";
    return;
  }
  LatentStepper::Checkpoint start = initial_;  // the scene's initial pose, at rest, now
  start.z_prev = start.z;
  start.t = before.t, start.n = before.n;
  rom_.restore(start);
  if (attempt(again)) {
    health_.last_recovery = when + why + "; at rest in place, " + again +
                            "; redone from the scene's initial pose at rest";
    return;
  }
  start.t = before.t + rom_.dt(), start.n = before.n + 1;  // held there; time goes on
  rom_.restore(start);
  health_.last_recovery = when + why + "; held at the scene's initial pose (" + again + ")";
}

void StepGuard::advance_frame() {
  for (int i = 0; i < rom_.steps_per_frame(); ++i) step();
}

}  // namespace nsf
