#pragma once
// The simple alternatives a reduced-order row is measured against (docs/RESULTS.md, issue #25):
// what a user could do instead of running the ROM, each scored with δ (eq. 11, frames 1…N)
// against the same ground truth.
//   look-up: the training run nearest in μ, played back;
//   interpolation: the two training runs around μ, blended linearly in μ frame by frame (the two
//     nearest, extrapolating, where μ lies outside the training range), and linearly in t where
//     a run's frame times are not the truth's;
//   over a sweep with "vary" axes (data/sweep_spec.h), both in the box of μ and the axes, each
//     scaled by its range over the training runs: look-up the nearest run, interpolation the
//     d + 1 nearest (d axes in all) blended by inverse squared distance;
//   coarse engine: nsf's own full-order engine on a coarser scene at the same μ, every
//     ground-truth particle following the coarse particles around it in the rest configuration
//     (linear moving least squares over the 8 nearest of its own object, nn/point_interpolation.h),
//     with its step time, so that its speed-up sits beside the ROM's.
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "io/run_reader.h"
#include "rom/setup/scene_file.h"

namespace nsf {

struct TrainingRun {
  std::string path;
  double mu = 0;
  std::map<std::string, double> axes;  // its "vary" axes' values by name (none: μ only)
};

struct Baselines {
  double lookup_delta = -1, lookup_mu = 0;  // < 0: not measured
  double interp_delta = -1, interp_mu_lo = 0, interp_mu_hi = 0;
  bool interp_extrapolated = false;  // μ outside [interp_mu_lo, interp_mu_hi]
  int interp_runs = 2;               // runs blended (more over a sweep with axes)
  double lookup_distance = 0;        // to the look-up's run in the scaled box (axes only)
  double coarse_delta = -1;
  double coarse_seconds = -1;  // the coarse engine's steps only, as fom_seconds
  size_t coarse_particles = 0;
  std::string coarse_scene;  // what it ran, e.g. "metal_small" or "metal_small at 2x dx"
};

// Look-up and interpolation from `runs` (at least two, of the truth's scene: same particles and
// rest positions), over the truth's frames 1…frames. Throws nsf::Error naming the run at fault.
// `axes`: the truth's values of the runs' axes; empty, or runs without axes: μ alone.
void measure_sweep_baselines(const std::vector<TrainingRun>& runs, double mu,
                             const RunReader& truth, int frames, Baselines& out,
                             const std::map<std::string, double>& axes = {});

// The coarse engine: `scene` (already at μ) built from `file`, run for the truth's frames with
// `threads` OpenMP threads. Its frames must fall at the truth's times. Throws nsf::Error.
void measure_coarse_baseline(const SceneFile& file, const nlohmann::json& scene,
                             const RunReader& truth, int frames, int threads, bool quiet,
                             Baselines& out);

// --set overrides that make `scene` k times coarser (k > 1): Δx·k, and Δt·k with substeps/k
// where that is a whole number (else Δt stays, so a frame still spans the same time).
std::vector<std::string> coarser_overrides(const nlohmann::json& scene, double k);

}  // namespace nsf
