#pragma once
// A training dataset as written by `nsf sweep`: a directory with manifest.json and one run file
// per simulation (train_k.h5, test_k.h5, attribute `mu`). No torch here: the trainer and `nsf eval`
// turn frames into tensors themselves.
#include <memory>
#include <string>
#include <vector>

#include "core/types.h"
#include "data/training_box.h"
#include "io/run_reader.h"

namespace nsf {

struct SimulationFile {
  std::string path;
  bool has_mu = false;
  double mu = 0;
  size_t frames = 0;
  // Its swept values (μ by the sweep's parameter name, and the "vary" axes) as one-point ranges,
  // and where its colliders went: this run's part of a model's training box.
  TrainingBox box;
};

// One frame in single precision, the networks' precision. Row-major per particle:
// x (P×3), tau (P×6: xx yy zz xy yz xz), C (P×9).
struct FrameData {
  std::vector<float> x, tau, C;
};

class Dataset {
 public:
  // Opens every run listed by <dir>/manifest.json ("train"/"test" arrays of file names, or
  // "runs" of {"file", "split"} objects), or, without a manifest, <dir>/train_*.h5 and
  // <dir>/test_*.h5. Checks that all runs share one scene (particle count and rest positions)
  // and that either all or none carry `mu`.
  // Refuses an incomplete dataset (nn/dataset_gaps.h: a killed or partial sweep), naming the
  // missing and unfinished runs; with allow_incomplete it opens the runs there are, and
  // incomplete() says what is missing.
  explicit Dataset(const std::string& dir, bool allow_incomplete = false);
  ~Dataset();
  Dataset(Dataset&&) noexcept;
  Dataset& operator=(Dataset&&) noexcept;

  const std::string& dir() const { return dir_; }
  // Empty for a complete dataset; else what is missing (allow_incomplete).
  const std::string& incomplete() const { return incomplete_; }
  const std::string& scene_name() const { return scene_name_; }
  size_t particle_count() const { return X_.size(); }
  const std::vector<Vec3>& rest_positions() const { return X_; }
  bool has_mu() const { return has_mu_; }
  // Per-particle rest volume V⁰ and object id, and the grid (Δx, domain corner) of the runs.
  const std::vector<double>& volumes() const { return volume_; }
  const std::vector<uint16_t>& objects() const { return object_; }
  double grid_dx() const { return dx_; }
  const Vec3& domain_lo() const { return domain_lo_; }
  // The scene JSON the first training run stored (empty for runs written without one).
  const std::string& scene_json() const;
  const std::vector<SimulationFile>& train() const { return train_; }
  const std::vector<SimulationFile>& test() const { return test_; }

  // Reads frame k of a run (any split), converting to float.
  FrameData read_frame(const SimulationFile& sim, size_t k) const;
  std::vector<Vec3> read_positions(const SimulationFile& sim, size_t k) const;
  // One field of frame k, "x", "tau" or "C", in FrameData's layout: the same floats as
  // read_frame's, for a fraction of the reading.
  std::vector<float> read_field(const SimulationFile& sim, size_t k,
                                const std::string& field) const;

 private:
  const RunReader& reader(const SimulationFile& sim) const;

  std::string dir_, scene_name_, incomplete_;
  std::vector<Vec3> X_;
  std::vector<double> volume_;
  std::vector<uint16_t> object_;
  double dx_ = 0;
  Vec3 domain_lo_ = Vec3::Zero();
  bool has_mu_ = false;
  std::vector<SimulationFile> train_, test_;
  std::vector<std::unique_ptr<RunReader>> readers_;  // train runs, then test runs
};

// The box the training runs span (data/training_box.h): the union of the train split's runs.
TrainingBox training_box(const Dataset& data);

// The training frames, all (run, frame) pairs of the train split, cached in RAM while they fit
// a budget and streamed from the run files otherwise. A process of a team of `shares`
// (`mpirun -np K nsf train`, nn/train/gradient_team.h) holds only its share: the frames i with
// i mod shares == share; every index stays global. `positions_only`: the frames hold x alone
// (a basis model's training reads τ and C once, for their bases, from the run files).
class FrameStore {
 public:
  FrameStore(const Dataset& data, double budget_gib, int share = 0, int shares = 1,
             bool positions_only = false);
  size_t size() const { return index_.size(); }  // frames over all training runs
  size_t sim_of(size_t i) const { return index_[i].first; }
  size_t frame_of(size_t i) const { return index_[i].second; }
  // The training frame of frame k of training run `sim`; kNone when there is no such frame.
  static constexpr size_t kNone = size_t(-1);
  size_t index_of(size_t sim, size_t k) const;
  // Whether frame i is of this process's share (always, for a single process).
  bool holds(size_t i) const { return i % size_t(shares_) == size_t(share_); }
  // Frame i; valid until the next call when streaming. A frame outside this process's share is
  // read from its run file each time (and is valid until the next such call).
  const FrameData& get(size_t i) const;
  bool cached() const { return cached_; }
  bool positions_only() const { return positions_only_; }
  double budget_gib() const { return budget_gib_; }
  double cached_gib() const { return cached_gib_; }  // 0 when streaming

 private:
  const Dataset& data_;
  std::vector<std::pair<size_t, size_t>> index_;
  std::vector<size_t> run_start_;  // per training run, the index of its frame 0
  int share_ = 0, shares_ = 1;
  bool cached_ = false, positions_only_ = false;
  double budget_gib_ = 0, cached_gib_ = 0;
  FrameData read(size_t i) const;
  mutable std::vector<FrameData> frames_;  // the share's frames, frame i at i / shares_
  mutable FrameData scratch_;
  mutable size_t scratch_index_ = kNone;  // the frame scratch_ holds: read again only for another
};

}  // namespace nsf
