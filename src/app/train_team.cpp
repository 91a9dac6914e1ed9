#include "app/train_team.h"

#include <algorithm>
#include <chrono>
#include <climits>
#include <string>
#include <thread>

#include "app/mpi_call.h"
#include "core/error.h"

namespace nsf::app {

#if NSF_WITH_MPI
namespace {

// MPI counts are ints: longer buffers go in pieces.
constexpr size_t kPiece = size_t(INT_MAX) / 2;

// Waits for a collective, sleeping between polls: a blocking call spins on its core while the
// other processes compute their share of the step (or process 0 the one-time statistics), and
// where processes share cores (a busy machine, --oversubscribe) that spinning takes the CPU from
// the very process it waits for.
void wait_for(MPI_Request& request, const char* what) {
  for (;;) {
    int done = 0;
    check_mpi(MPI_Test(&request, &done, MPI_STATUS_IGNORE), what);
    if (done) return;
    std::this_thread::sleep_for(std::chrono::microseconds(50));
  }
}

// Why MPI and not torch's c10d with gloo: MPI is already the launcher and the transport of the
// sweeps (one mechanism for a cluster), and Debian's LibTorch 1.13 ships no stable public C++
// API for its process groups.
class MpiGradientTeam : public GradientTeam {
 public:
  MpiGradientTeam(int rank, int size) : rank_(rank), size_(size) {}
  int rank() const override { return rank_; }
  int size() const override { return size_; }

  void sum(float* data, size_t n) override {
    // Open MPI's reductions (recursive doubling, ring) hand every process the same sum: each
    // partial sum is formed once, or by commutative pairs, which floats add exactly alike.
    for (size_t at = 0; at < n; at += kPiece) {
      MPI_Request request;
      check_mpi(MPI_Iallreduce(MPI_IN_PLACE, data + at, int(std::min(kPiece, n - at)), MPI_FLOAT,
                               MPI_SUM, MPI_COMM_WORLD, &request),
                "summing the gradients");
      wait_for(request, "summing the gradients");
    }
  }

  void broadcast(std::string& bytes) override {
    const char* what = "broadcast from process 0";
    unsigned long long length = bytes.size();
    MPI_Request request;
    check_mpi(MPI_Ibcast(&length, 1, MPI_UNSIGNED_LONG_LONG, 0, MPI_COMM_WORLD, &request), what);
    wait_for(request, what);
    bytes.resize(size_t(length));
    for (size_t at = 0; at < bytes.size(); at += kPiece) {
      check_mpi(MPI_Ibcast(bytes.data() + at, int(std::min(kPiece, bytes.size() - at)), MPI_CHAR, 0,
                           MPI_COMM_WORLD, &request),
                what);
      wait_for(request, what);
    }
  }

 private:
  int rank_, size_;
};

}  // namespace
#endif

std::unique_ptr<GradientTeam> make_gradient_team(const SweepRanks& ranks) {
#if NSF_WITH_MPI
  if (ranks.size() > 1) return std::make_unique<MpiGradientTeam>(ranks.rank(), ranks.size());
#endif
  (void)ranks;
  return nullptr;
}

}  // namespace nsf::app
