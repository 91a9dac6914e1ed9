#pragma once
// `mpirun -np K nsf sweep scene.json -o DIR`: K processes share one sweep over MPI
// (docs/DATASETS.md, "Sweeps across machines"). Run i of those not yet complete goes to process
// i mod K; each writes its runs as one process would (temporary file, then rename); process 0
// writes the manifest once all have finished. Started without a launcher, nothing of MPI is
// touched and the sweep runs in this one process, as it always did.
#include <functional>
#include <memory>

#include "data/sweep.h"

namespace nsf::app {

// True when an MPI launcher (Open MPI's mpirun or mpiexec, or srun with PMIx) started this
// process, which it says in the environment.
bool launched_by_mpi();

class SweepRanks {
 public:
  SweepRanks();  // initialises MPI when launched_by_mpi()
  ~SweepRanks();
  SweepRanks(const SweepRanks&) = delete;
  SweepRanks& operator=(const SweepRanks&) = delete;

  int rank() const { return rank_; }
  int size() const { return size_; }
  // The cores this process may use: those it may run on, and no more than its share of the
  // machine's when several processes of the job share one machine.
  int cores() const;
  // The team run_sweep works with; null for a single process.
  SweepTeam* team() { return team_.get(); }
  // After an error on this process: ends every process of the job (MPI_Abort), so that none
  // waits forever for this one. Their runs in progress are lost; finished runs stay.
  [[noreturn]] void abort(int code) const;
  // Runs `body`. An error on one process of several is printed with the process's number and
  // ends the job (abort), since the others may be waiting for this one in a collective; a single
  // process rethrows it.
  void run(const std::function<void()>& body) const;

 private:
  bool mpi_ = false;
  int rank_ = 0, size_ = 1, local_size_ = 1;
  std::unique_ptr<SweepTeam> team_;
};

}  // namespace nsf::app
