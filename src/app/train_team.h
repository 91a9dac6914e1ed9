#pragma once
// `mpirun -np K nsf train DATA --out M`: K processes train one model (docs/TRAINING.md,
// "Training across machines"), summing their gradients with MPI_Allreduce after every step
// (nn/train/gradient_team.h says what each process computes).
#include <memory>

#include "app/sweep_ranks.h"
#include "nn/train/gradient_team.h"

namespace nsf::app {

// The processes of `ranks` as a GradientTeam over MPI_COMM_WORLD; null for a single process.
std::unique_ptr<GradientTeam> make_gradient_team(const SweepRanks& ranks);

}  // namespace nsf::app
