#pragma once
// Several processes training one model together (`mpirun -np K nsf train`; docs/TRAINING.md,
// "Training across machines"). app/train_team.cpp implements it over MPI, so that this layer
// knows no MPI. Every process draws the same global batch from the same seeded generator and
// computes the entries whose frames it holds (FrameStore's share); their gradients, each
// weighted by the global batch's size, are summed, so that every step equals one process's
// step on the whole batch up to the order of the floating-point sums.
#include <cstddef>
#include <string>

namespace nsf {

class GradientTeam {
 public:
  virtual ~GradientTeam() = default;
  virtual int rank() const = 0;  // 0 .. size() - 1; process 0 writes every file
  virtual int size() const = 0;
  // Replaces data[0 .. n) by its sum over the processes, the same on every process. Every
  // process calls it with the same n at the same point of the training.
  virtual void sum(float* data, size_t n) = 0;
  // Process 0's bytes to every process (the others' `bytes` are replaced).
  virtual void broadcast(std::string& bytes) = 0;
};

}  // namespace nsf
