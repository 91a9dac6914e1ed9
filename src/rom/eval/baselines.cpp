#include "rom/eval/baselines.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "core/error.h"
#include "core/progress.h"
#include "core/timer.h"
#include "mpm/simulation.h"
#include "nn/field_checks.h"
#include "nn/point_interpolation.h"

namespace nsf {

namespace {

// The sums of eq. (11) over frames.
void add_frame(ErrorSum& sum, const std::vector<Vec3>& x, const std::vector<Vec3>& truth) {
  for (size_t p = 0; p < truth.size(); ++p) sum.add(x[p], truth[p]);
}

// A training run's positions at any time of its span: linear between its two frames around t.
class RunPlayback {
 public:
  RunPlayback(const std::string& path, const RunReader& truth) : run_(path) {
    if (run_.particle_count() != truth.particle_count() ||
        run_.rest_positions() != truth.rest_positions())
      fail("baselines: training run ", path, " holds other particles than the ground truth ",
           truth.path(), " (", run_.particle_count(), " against ", truth.particle_count(), ")");
  }
  std::vector<Vec3> at(double t) const {
    const std::vector<double>& times = run_.times();
    const double tol = 1e-6 * std::max(1.0, std::abs(t));
    if (times.empty() || t > times.back() + tol || t < times.front() - tol)
      fail("baselines: training run ", run_.path(), " spans t = [",
           times.empty() ? 0.0 : times.front(), ", ", times.empty() ? 0.0 : times.back(),
           "] s, the ground truth needs t = ", t, " s");
    const size_t k = size_t(std::lower_bound(times.begin(), times.end(), t - tol) - times.begin());
    if (std::abs(times[k] - t) <= tol) return run_.read_positions(k);
    const double w = (t - times[k - 1]) / (times[k] - times[k - 1]);
    std::vector<Vec3> a = run_.read_positions(k - 1);
    const std::vector<Vec3> b = run_.read_positions(k);
    for (size_t p = 0; p < a.size(); ++p) a[p] += w * (b[p] - a[p]);
    return a;
  }

 private:
  RunReader run_;
};

// Every truth particle as a weighted sum of coarse particles of its own object (all of them
// where the coarse scene has none of that object).
PointInterpolation carry_to_truth(const Particles& coarse, const RunReader& truth) {
  std::map<uint16_t, std::vector<uint32_t>> coarse_of, truth_of;
  for (size_t p = 0; p < coarse.size(); ++p) coarse_of[coarse.object[p]].push_back(uint32_t(p));
  for (size_t p = 0; p < truth.particle_count(); ++p)
    truth_of[truth.object()[p]].push_back(uint32_t(p));
  std::vector<std::vector<std::pair<uint32_t, float>>> rows(truth.particle_count());
  for (const auto& [object, points] : truth_of) {
    std::vector<uint32_t> from =
        coarse_of.count(object) ? coarse_of[object] : std::vector<uint32_t>();
    if (from.empty())
      for (size_t p = 0; p < coarse.size(); ++p) from.push_back(uint32_t(p));
    std::vector<Vec3> X_from, X_to;
    for (uint32_t p : from) X_from.push_back(coarse.X[p]);
    for (uint32_t p : points) X_to.push_back(truth.rest_positions()[p]);
    const PointInterpolation in = interpolate_points(X_from, X_to);
    for (size_t i = 0; i < points.size(); ++i)
      for (uint32_t e = in.start[i]; e < in.start[i + 1]; ++e)
        rows[points[i]].emplace_back(from[in.particle[e]], in.weight[e]);
  }
  PointInterpolation out;
  out.start.push_back(0);
  for (const auto& row : rows) {
    for (const auto& [p, w] : row) out.particle.push_back(p), out.weight.push_back(w);
    out.start.push_back(uint32_t(out.particle.size()));
  }
  return out;
}

}  // namespace

namespace {

// Look-up and interpolation in the box of μ and the axes: distances with each coordinate scaled
// by its range over the runs; the d + 1 nearest blended by inverse squared distance.
void measure_in_box(const std::vector<TrainingRun>& runs, double mu,
                    const std::map<std::string, double>& axes, const RunReader& truth, int frames,
                    Baselines& out) {
  std::vector<std::vector<double>> points(runs.size());
  std::vector<double> query = {mu};
  for (const auto& [name, value] : axes) query.push_back(value);
  for (size_t i = 0; i < runs.size(); ++i) {
    points[i].push_back(runs[i].mu);
    for (const auto& [name, value] : axes) {
      auto it = runs[i].axes.find(name);
      if (it == runs[i].axes.end())
        fail("baselines: training run ", runs[i].path, " has no value of axis '", name, "'");
      points[i].push_back(it->second);
    }
  }
  std::vector<double> scale(query.size(), 1.0);
  for (size_t k = 0; k < query.size(); ++k) {
    double lo = points[0][k], hi = points[0][k];
    for (const auto& p : points) lo = std::min(lo, p[k]), hi = std::max(hi, p[k]);
    if (hi > lo) scale[k] = 1 / (hi - lo);
  }
  std::vector<std::pair<double, size_t>> by_distance;
  for (size_t i = 0; i < runs.size(); ++i) {
    double d2 = 0;
    for (size_t k = 0; k < query.size(); ++k)
      d2 += std::pow((points[i][k] - query[k]) * scale[k], 2);
    by_distance.emplace_back(std::sqrt(d2), i);
  }
  std::sort(by_distance.begin(), by_distance.end());
  const size_t blend = std::min(runs.size(), query.size() + 1);
  std::vector<double> w(blend);
  double sum = 0;
  for (size_t j = 0; j < blend; ++j)
    sum += w[j] =
        by_distance[0].first == 0 ? (j == 0 ? 1.0 : 0.0) : 1 / std::pow(by_distance[j].first, 2);
  std::vector<RunPlayback> near;
  for (size_t j = 0; j < blend; ++j) near.emplace_back(runs[by_distance[j].second].path, truth);
  ErrorSum lookup, interp;
  for (int f = 1; f <= frames; ++f) {
    const double t = truth.times()[size_t(f)];
    const std::vector<Vec3> phi = truth.read_positions(size_t(f));
    std::vector<Vec3> x0 = near[0].at(t), x(x0.size(), Vec3::Zero());
    add_frame(lookup, x0, phi);
    for (size_t j = 0; j < blend; ++j) {
      const std::vector<Vec3> xj = j == 0 ? x0 : near[j].at(t);
      for (size_t p = 0; p < x.size(); ++p) x[p] += (w[j] / sum) * xj[p];
    }
    add_frame(interp, x, phi);
  }
  const TrainingRun& nearest = runs[by_distance[0].second];
  out.lookup_mu = nearest.mu;
  out.lookup_distance = by_distance[0].first;
  out.lookup_delta = lookup.relative();
  out.interp_runs = int(blend);
  out.interp_mu_lo = out.interp_mu_hi = nearest.mu;
  for (size_t j = 0; j < blend; ++j) {
    out.interp_mu_lo = std::min(out.interp_mu_lo, runs[by_distance[j].second].mu);
    out.interp_mu_hi = std::max(out.interp_mu_hi, runs[by_distance[j].second].mu);
  }
  out.interp_extrapolated = false;
  out.interp_delta = interp.relative();
}

}  // namespace

void measure_sweep_baselines(const std::vector<TrainingRun>& runs_in, double mu,
                             const RunReader& truth, int frames, Baselines& out,
                             const std::map<std::string, double>& axes) {
  if (runs_in.size() < 2)
    fail("baselines: look-up and interpolation need at least two training runs, got ",
         runs_in.size());
  if (!axes.empty()) return measure_in_box(runs_in, mu, axes, truth, frames, out);
  std::vector<TrainingRun> runs = runs_in;
  std::sort(runs.begin(), runs.end(),
            [](const TrainingRun& a, const TrainingRun& b) { return a.mu < b.mu; });
  // Nearest in μ (the lower one on a tie); the pair around μ, or the two nearest outside.
  size_t nearest = 0;
  for (size_t i = 1; i < runs.size(); ++i)
    if (std::abs(runs[i].mu - mu) < std::abs(runs[nearest].mu - mu)) nearest = i;
  size_t hi = size_t(std::upper_bound(runs.begin(), runs.end(), mu,
                                      [](double m, const TrainingRun& r) { return m < r.mu; }) -
                     runs.begin());
  hi = std::clamp<size_t>(hi, 1, runs.size() - 1);
  const size_t lo = hi - 1;
  if (runs[lo].mu == runs[hi].mu)
    fail("baselines: training runs ", runs[lo].path, " and ", runs[hi].path,
         " have the same mu = ", runs[lo].mu, ": nothing to interpolate between");
  const double w = (mu - runs[lo].mu) / (runs[hi].mu - runs[lo].mu);

  const RunPlayback near(runs[nearest].path, truth), a(runs[lo].path, truth),
      b(runs[hi].path, truth);
  ErrorSum lookup, interp;
  for (int f = 1; f <= frames; ++f) {
    const double t = truth.times()[size_t(f)];
    const std::vector<Vec3> phi = truth.read_positions(size_t(f));
    add_frame(lookup, near.at(t), phi);
    std::vector<Vec3> x = a.at(t);
    const std::vector<Vec3> xb = b.at(t);
    for (size_t p = 0; p < x.size(); ++p) x[p] += w * (xb[p] - x[p]);
    add_frame(interp, x, phi);
  }
  out.lookup_mu = runs[nearest].mu;
  out.lookup_delta = lookup.relative();
  out.interp_mu_lo = runs[lo].mu;
  out.interp_mu_hi = runs[hi].mu;
  out.interp_extrapolated = w < 0 || w > 1;
  out.interp_delta = interp.relative();
}

void measure_coarse_baseline(const SceneFile& file, const nlohmann::json& js,
                             const RunReader& truth, int frames, int threads, bool quiet,
                             Baselines& out) {
  omp_set_num_threads(std::max(1, threads));
  Simulation sim(build_scene_file(file, js));
  const SimSettings& s = sim.settings();
  const double frame_dt = s.substeps * s.dt;
  for (int f = 1; f <= frames; ++f) {
    const double t = truth.times()[size_t(f)];
    if (std::abs(f * frame_dt - t) > 1e-6 * std::max(1.0, t))
      fail("baselines: the coarse scene ", file.path, " puts frame ", f, " at t = ", f * frame_dt,
           " s, the ground truth at t = ", t, " s: it needs the same frame times");
  }
  if (s.frames < frames)
    fail("baselines: the coarse scene ", file.path, " has ", s.frames, " frames, the truth ",
         frames);
  const PointInterpolation carry = carry_to_truth(sim.particles(), truth);
  ErrorSum delta;
  std::vector<Vec3> x(truth.particle_count());
  double seconds = 0;
  Progress progress("coarse engine", frames, "frames");
  for (int f = 1; f <= frames; ++f) {
    const double t0 = now_seconds();
    sim.advance_frame();
    seconds += now_seconds() - t0;
    const std::vector<Vec3>& xc = sim.particles().x;
    for (size_t p = 0; p < x.size(); ++p) {
      x[p].setZero();
      for (uint32_t e = carry.start[p]; e < carry.start[p + 1]; ++e)
        x[p] += double(carry.weight[e]) * xc[carry.particle[e]];
    }
    add_frame(delta, x, truth.read_positions(size_t(f)));
    if (!quiet) progress.update(f);
  }
  if (!quiet) progress.finish();
  out.coarse_delta = delta.relative();
  out.coarse_seconds = seconds;
  out.coarse_particles = sim.particles().size();
}

std::vector<std::string> coarser_overrides(const nlohmann::json& scene, double k) {
  if (!(k > 1)) fail("baselines: a coarser scene needs a factor above 1, got ", k);
  const nlohmann::json& sim = scene.at("simulation");
  auto number = [](const char* key, double v) {
    char b[96];
    std::snprintf(b, sizeof b, "simulation.%s=%.17g", key, v);
    return std::string(b);
  };
  std::vector<std::string> o = {number("dx", k * sim.at("dx").get<double>())};
  const int substeps = sim.value("substeps", 1);
  const double fewer = substeps / k;
  if (std::abs(fewer - std::round(fewer)) < 1e-9 && fewer >= 1) {
    o.push_back(number("dt", k * sim.at("dt").get<double>()));
    o.push_back("simulation.substeps=" + std::to_string(int(std::round(fewer))));
  }
  return o;
}

}  // namespace nsf
