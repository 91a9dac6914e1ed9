#include "app/sweep_ranks.h"

#include <omp.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <thread>

#include "app/mpi_call.h"
#include "core/error.h"

namespace nsf::app {

#if NSF_WITH_MPI
namespace {

// The sweep's processes over MPI_COMM_WORLD. Process 0 decides what is pending and writes the
// manifest.
class MpiTeam : public SweepTeam {
 public:
  MpiTeam(int rank, int size) : rank_(rank), size_(size) {}

  std::vector<int> share(const std::vector<int>& pending) override {
    // Process 0's view decides, so that every run goes to exactly one process even where
    // processes see the shared folder differently (a network file system's caches).
    int count = int(pending.size());
    check_mpi(MPI_Bcast(&count, 1, MPI_INT, 0, MPI_COMM_WORLD), "broadcast of the pending runs");
    std::vector<int> all = rank_ == 0 ? pending : std::vector<int>(size_t(count));
    check_mpi(MPI_Bcast(all.data(), count, MPI_INT, 0, MPI_COMM_WORLD),
              "broadcast of the pending runs");
    std::vector<int> mine;
    for (int k = rank_; k < count; k += size_) mine.push_back(all[size_t(k)]);
    return mine;
  }

  void collect(const std::vector<int>& done,
               const std::function<void(const std::vector<int>&)>& write_manifest) override {
    int count = int(done.size());
    std::vector<int> counts(size_t(size_), 0), offsets(size_t(size_), 0);
    check_mpi(MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD),
              "gathering the finished runs");
    for (int r = 1; r < size_; ++r)
      offsets[size_t(r)] = offsets[size_t(r - 1)] + counts[size_t(r - 1)];
    std::vector<int> all(rank_ == 0 ? size_t(offsets.back() + counts.back()) : 0);
    check_mpi(MPI_Gatherv(done.data(), count, MPI_INT, all.data(), counts.data(), offsets.data(),
                          MPI_INT, 0, MPI_COMM_WORLD),
              "gathering the finished runs");
    std::exception_ptr error;
    if (rank_ == 0) {
      std::sort(all.begin(), all.end());
      try {
        write_manifest(all);
      } catch (...) {
        error = std::current_exception();
      }
    }
    // No process goes on (and may end the job on an error of its own) before the manifest is
    // written.
    check_mpi(MPI_Barrier(MPI_COMM_WORLD), "waiting for the manifest");
    if (error) std::rethrow_exception(error);
  }

 private:
  int rank_, size_;
};

}  // namespace
#endif

bool launched_by_mpi() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK"})
    if (std::getenv(name)) return true;
  return false;
}

SweepRanks::SweepRanks() {
  if (!launched_by_mpi()) return;
#if !NSF_WITH_MPI
  fail(
      "started by mpirun, but this nsf was built without MPI (cmake -DNSF_WITH_MPI=OFF): run "
      "it as one process, or rebuild with Open MPI's development files");
#else
  // Only this (the main) thread calls MPI; the simulation threads never do.
  int provided = 0;
  check_mpi(MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided), "initialisation");
  mpi_ = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
  MPI_Comm local;
  check_mpi(MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &local),
            "finding the processes on this machine");
  MPI_Comm_size(local, &local_size_);
  MPI_Comm_free(&local);
  if (size_ > 1) team_ = std::make_unique<MpiTeam>(rank_, size_);
#endif
}

SweepRanks::~SweepRanks() {
#if NSF_WITH_MPI
  if (mpi_) MPI_Finalize();
#endif
}

int SweepRanks::cores() const {
  const int usable = omp_get_num_procs();  // respects the launcher's binding
  if (local_size_ <= 1) return usable;
  const int machine = std::max(1, int(std::thread::hardware_concurrency()));
  return std::max(1, std::min(usable, machine / local_size_));
}

void SweepRanks::run(const std::function<void()>& body) const {
  try {
    body();
  } catch (const std::exception& e) {
    if (size_ == 1) throw;
    std::fprintf(stderr, "\nnsf: error (process %d of %d): %s\n", rank_, size_, e.what());
    std::fflush(stderr);
    abort(1);
  }
}

void SweepRanks::abort(int code) const {
#if NSF_WITH_MPI
  if (mpi_) MPI_Abort(MPI_COMM_WORLD, code);
#endif
  std::exit(code);
}

}  // namespace nsf::app
