#include "nn/evaluate.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>

#include "core/error.h"
#include "nn/basis_decoders.h"
#include "nn/dataset.h"
#include "nn/field_checks.h"
#include "nn/held_out_points.h"
#include "nn/latent_inversion.h"
#include "nn/model/neural_model.h"
#include "nn/network_samples.h"
#include "nn/neural_fields.h"

namespace nsf {

namespace {

// The field of `truth` (dim values per particle, all particles) projected onto a basis: the
// coefficients c* minimise the weighted error, and the modes are orthonormal in that weight, so
// c* = Σ_p B_pᵀ W² (f_p − mean_p). Writes the projection into `out`.
void project(const PointBasis& b, const std::vector<double>& weights, const float* truth,
             std::vector<float>& out) {
  const size_t d = size_t(b.dim), K = size_t(b.K);
  Eigen::VectorXd c = Eigen::VectorXd::Zero(b.K);
  for (size_t p = 0; p < b.points; ++p)
    for (size_t i = 0; i < d; ++i) {
      const double w2 = weights[i] * weights[i];
      const double r = w2 * (double(truth[p * d + i]) - b.mean[p * d + i]);
      const float* row = &b.modes[(p * d + i) * K];
      for (size_t k = 0; k < K; ++k) c[Eigen::Index(k)] += r * row[k];
    }
  const Eigen::VectorXf cf = c.cast<float>();
  out.resize(b.points * d);
  for (size_t p = 0; p < b.points; ++p) b.value(p, cf, &out[p * d]);
}

}  // namespace

std::vector<EvalRow> evaluate_model(const std::string& model_path, const std::string& data_dir,
                                    const EvalOptions& o) {
  NeuralFields nf = NeuralFields::load(model_path);
  const Dataset data(data_dir, o.allow_incomplete);
  if (!data.incomplete().empty())
    std::fprintf(stderr, "WARNING: %s\n  --allow-incomplete: evaluating on the runs it has\n",
                 data.incomplete().c_str());
  nf.check_scene(data.scene_name(), data.rest_positions(), "dataset " + data_dir);

  std::vector<SimulationFile> runs;
  if (o.split == "test" || o.split == "all") runs = data.test();
  if (o.split == "train" || o.split == "all")
    runs.insert(runs.end(), data.train().begin(), data.train().end());
  if (o.split != "test" && o.split != "train" && o.split != "all")
    fail("eval: split must be test, train or all, got '", o.split, "'");
  if (runs.empty()) fail("dataset ", data_dir, " has no ", o.split, " runs to evaluate");

  const size_t P = data.particle_count();
  std::vector<size_t> subset;
  const size_t n = o.max_particles > 0 ? std::min(o.max_particles, P) : P;
  for (size_t i = 0; i < n; ++i) subset.push_back(i * P / n);
  std::vector<Vec3> X;
  std::vector<double> volume;
  std::vector<uint16_t> object;
  for (size_t p : subset) {
    X.push_back(data.rest_positions()[p]);
    volume.push_back(data.volumes()[p]), object.push_back(data.objects()[p]);
  }
  const NeuralFields::Points pts = nf.prepare(X);
  const SmoothFit smooth(X, object, o.poly_degree);
  std::optional<HeldOutPoints> held;
  if (o.held_out_stride > 0) held.emplace(nf, o.held_out_stride, o.interpolation, o.neighbours);
  // The held-out particles read the fields of every particle: those of the subset when it is all
  // of them, else their own evaluation.
  std::optional<NeuralFields::Points> all_pts;
  if (held && n < P) all_pts.emplace(nf.prepare(data.rest_positions()));
  std::optional<FrameLatentRefiner> refiner;
  if (o.refine_iterations > 0) refiner.emplace(nf, data.rest_positions(), o.refine_iterations);

  std::vector<EvalRow> rows;
  std::vector<Vec3> x;
  std::vector<Mat3> tau, C;
  std::vector<Vec3> x_true(n);
  std::vector<Mat3> tau_true(n), C_true(n);
  for (const SimulationFile& run : runs) {
    EvalRow row;
    row.run = std::filesystem::path(run.path).filename().string();
    row.mu = run.mu, row.has_mu = run.has_mu, row.particles = n;
    double ex = 0, nx = 0, px = 0, ex_encoded = 0;
    ErrorSum stress, affine, force, stress_poly_fit, affine_poly_fit, stress_proj, affine_proj;
    const BasisDecoders* bases = nf.bases();
    if (held) held->start();
    // Eq. (11) sums over n = 1…N: frame 0 is the initial state, not a prediction.
    for (size_t k = std::min<size_t>(1, run.frames - 1); k < run.frames;
         k += std::max<size_t>(1, o.frame_stride)) {
      const FrameData f = data.read_frame(run, k);
      std::vector<Vec3> full(P);
      for (size_t p = 0; p < P; ++p) full[p] = Vec3(f.x[3 * p], f.x[3 * p + 1], f.x[3 * p + 2]);
      Latent z = nf.encode(full);
      if (refiner) {
        nf.deform(pts, z, x);
        for (size_t i = 0; i < n; ++i) ex_encoded += (x[i] - full[subset[i]]).squaredNorm();
        z = refiner->refine(f.x.data(), z);
      }
      // τ or C of a model that reads the latent velocity: ż of the frame's own particle velocities.
      Latent zdot;
      if (bases && bases->reads_velocity())
        zdot = bases->latent_velocity(z, data.read_field(run, k, "v").data());
      nf.deform(pts, z, x);
      nf.stress(pts, z, run.mu, tau, &zdot);
      nf.affine(pts, z, C, run.mu, &zdot);
      require_finite_fields(z, x, tau, C, "model " + model_path, "run " + row.run, k);
      for (size_t i = 0; i < n; ++i) {
        const size_t p = subset[i];
        ex += (x[i] - full[p]).squaredNorm(), nx += full[p].squaredNorm();
        const Mat3 t = stored_stress(&f.tau[6 * p]);
        stress.add(tau[i], t);
        const Mat3 c = stored_affine(&f.C[9 * p]);
        affine.add(C[i], c);
        x_true[i] = full[p], tau_true[i] = t, C_true[i] = c;
      }
      add_grid_force_error(x_true, volume, tau, tau_true, data.domain_lo(), data.grid_dx(), force);
      if (held && !all_pts) held->add_frame(x, tau, C, full, f.tau.data(), f.C.data());
      if (all_pts) {
        std::vector<Vec3> xa;
        std::vector<Mat3> ta, ca;
        nf.deform(*all_pts, z, xa);
        nf.stress(*all_pts, z, run.mu, ta);
        nf.affine(*all_pts, z, ca, run.mu, &zdot);
        held->add_frame(xa, ta, ca, full, f.tau.data(), f.C.data());
      }
      smooth.add_residual(tau_true, stress_poly_fit);
      smooth.add_residual(C_true, affine_poly_fit);
      if (bases) {
        std::vector<float> u(3 * P), proj;
        for (size_t p = 0; p < P; ++p)
          for (int c = 0; c < 3; ++c) u[3 * p + c] = float(full[p][c] - bases->rest[p][c]);
        project(bases->u, {1, 1, 1}, u.data(), proj);
        for (size_t i = 0; i < n; ++i) {
          const size_t p = subset[i];
          const Vec3 x = bases->rest[p] + Vec3(proj[3 * p], proj[3 * p + 1], proj[3 * p + 2]);
          px += (x - full[p]).squaredNorm();
        }
        const double r2 = M_SQRT2;
        project(bases->tau, {1, 1, 1, r2, r2, r2}, f.tau.data(), proj);
        for (size_t i = 0; i < n; ++i)
          stress_proj.add(stored_stress(&proj[6 * subset[i]]), tau_true[i]);
        project(bases->C, std::vector<double>(9, 1.0), f.C.data(), proj);
        for (size_t i = 0; i < n; ++i)
          affine_proj.add(stored_affine(&proj[9 * subset[i]]), C_true[i]);
      }
      ++row.frames;
    }
    // A field that is zero throughout (no stress in a rigid drop) has no relative error: NaN.
    row.delta = nx > 0 ? std::sqrt(ex / nx) : NAN;
    row.delta_encoded = refiner ? (nx > 0 ? std::sqrt(ex_encoded / nx) : NAN) : row.delta;
    row.stress_error = stress.relative();
    row.affine_error = affine.relative();
    row.force_error = force.relative();
    row.stress_poly_fit = stress_poly_fit.relative(),
    row.affine_poly_fit = affine_poly_fit.relative();
    if (bases) {
      row.projection_delta = nx > 0 ? std::sqrt(px / nx) : NAN;
      row.projection_stress = stress_proj.relative();
      row.projection_affine = affine_proj.relative();
    }
    if (held) row.held_out = held->errors();
    rows.push_back(row);
  }
  return rows;
}

}  // namespace nsf
