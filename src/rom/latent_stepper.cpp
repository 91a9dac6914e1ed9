#include "rom/latent_stepper.h"

#include <torch/torch.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <optional>

#include "core/error.h"
#include "mpm/simulation.h"
#include "nn/model.h"
#include "nn/runtime.h"
#include "rom/field_gradients.h"
#include "rom/integration_set.h"
#include "rom/latent_inversion.h"
#include "rom/latent_prior.h"
#include "rom/linearized_field.h"
#include "rom/quadrature.h"

namespace nsf {

namespace {

torch::Tensor index_tensor(const std::vector<uint32_t>& ids) {
  torch::Tensor t = torch::empty({int64_t(ids.size())}, torch::kInt64);
  int64_t* p = t.data_ptr<int64_t>();
  for (size_t k = 0; k < ids.size(); ++k) p[k] = ids[k];
  return t;
}

torch::Tensor latent_row(const Latent& z) {
  return torch::from_blob(const_cast<double*>(z.data()), {1, int64_t(z.size())}, torch::kFloat64)
      .to(torch::kFloat32);
}

// Rows of a float tensor (n × 3) as positions.
void to_vec3(const torch::Tensor& t, std::vector<Vec3>& out) {
  const torch::Tensor d = t.to(torch::kFloat64).contiguous();
  const double* p = d.data_ptr<double>();
  out.resize(d.size(0));
  for (size_t k = 0; k < out.size(); ++k) out[k] = Vec3(p[3 * k], p[3 * k + 1], p[3 * k + 2]);
}

void rows_to_vec3(const std::vector<double>& v, std::vector<Vec3>& out) {
  out.resize(v.size() / 3);
  for (size_t k = 0; k < out.size(); ++k) out[k] = Vec3(v[3 * k], v[3 * k + 1], v[3 * k + 2]);
}

Mat3 symmetric_from6(const double* s) {  // xx yy zz xy yz xz, the run files' order
  Mat3 m;
  m << s[0], s[3], s[5], s[3], s[1], s[4], s[5], s[4], s[2];
  return m;
}

}  // namespace

struct LatentStepper::Impl {
  NeuralFields& fields;
  NeuralModel& model;
  RomOptions opt;
  double mu;
  std::unique_ptr<Simulation> sim;     // its particles() hold N only, rebuilt every step
  std::unique_ptr<LatentPrior> prior;  // when the model stores its training latents
  // Per particle of the scene, then per merged quadrature point (rom/quadrature.h): what the ROM
  // needs of the full particle set. mass and vol0 are the particles' own.
  size_t np = 0;  // |P|
  std::vector<Vec3> X;
  std::vector<double> mass, vol0;
  std::vector<uint16_t> material;
  std::vector<MaterialPoint> mat0;
  torch::Tensor Xn_particles;  // |P| × 3 normalised rest positions
  torch::Tensor Xn_all;        // the same, then the merged points'
  NeuralFields::Points all_points;

  std::vector<uint32_t> ranked, S;
  torch::Tensor Xn_S;
  Latent z, z_prev;
  double t = 0, dt = 0, T = 0, dx = 0;
  int per_frame = 1;
  long n = 0;

  NodeMarks marks;
  CandidateSet K;
  std::vector<int32_t> slot;  // particle → position in N, −1 elsewhere (reset after use)
  std::vector<uint32_t> N;
  std::vector<Vec3> x_cache;  // g on all particles at step cache_step
  long cache_step = -1;
  // The quadrature points that can join N (every particle unless thinned, rom/quadrature.h)
  // with their masses and volumes; when thinned, the points prepared for g.
  ThinnedQuadrature quad;
  NeuralFields::Points quad_points;
  // g(X, ẑ_n) on K from the last step: this step's g(X, ẑ_{n−1}) while K is unchanged.
  std::vector<Vec3> xK_last;
  bool xK_last_valid = false;
  long refreshed_at = -1;  // step of the last refresh: g(X, ẑ_n) on K is then known

  // The tangent cache (opt.linearize > 0): g on K, h and l on N through first-order expansions.
  std::unique_ptr<LinearizedField> lin_g, lin_h, lin_l;

  // --stress tracked / --affine tracked: every particle's own state, as the full-order engine
  // keeps it (F^E and plastic state updated from its G2P velocity gradient; APIC's C).
  struct Tracked {
    std::vector<Mat3> F, tau, C;
    std::vector<MaterialPoint> mp;
  } tracked;

  double sum_N = 0, sum_K = 0, last_residual = 0;
  double energy_after_mpm = 0, energy_after_inversion = 0;  // summed over steps, on S
  long refreshes = 0, misses = 0;
  RomTimes times;

  Impl(NeuralFields& f, Scene scene, double mu_, const RomOptions& o)
      : fields(f),
        model(f.model()),
        opt(o),
        mu(mu_),
        marks(scene.settings.domain_lo, scene.settings.dx,
              Grid(scene.settings.domain_lo, scene.settings.domain_hi, scene.settings.dx).dims()),
        K(o.halo) {
    const Particles& P = scene.particles;
    fields.check_scene(scene.name, P.X, "scene '" + scene.name + "'");
    X = P.X, mass = P.mass, vol0 = P.vol0, material = P.material, mat0 = P.mat;
    np = X.size();
    const std::vector<Vec3> v0 = P.v;
    const std::vector<Mat3> F0 = P.F;
    const double cfl_bound = opt.stress == StressSource::tracked ? cfl_time_step_bound(scene) : 0.0;
    const SimSettings& s = scene.settings;
    opt.affine = opt.resolved_affine();
    if (!(opt.dt_ratio > 0)) fail("rom: the time-step ratio must be positive, got ", opt.dt_ratio);
    if (!(opt.flip >= 0 && opt.flip <= 1)) fail("rom: --flip must lie in [0, 1], got ", opt.flip);
    // Not capped at the full-order CFL bound: the stress on N comes from h at ẑ, not from F
    // integrated over the step, so the grid's elastic waves do not set the ROM's stability
    // limit (sand_paper runs at 4Δt, 3.7 times the bound; docs/ROM.md, "Larger ROM steps").
    per_frame = std::max(1, int(std::lround(s.substeps / opt.dt_ratio)));
    dt = s.substeps * s.dt / per_frame;
    T = s.frames * s.substeps * s.dt;
    dx = s.dx;
    const int r = fields.latent_dim();
    const int min_samples = (r + 2) / 3;
    if (opt.sampling.count < min_samples || size_t(opt.sampling.count) > X.size())
      fail("rom: |S| = ", opt.sampling.count, " sample particles is out of range: need at least ",
           min_samples, " (r/3 for r = ", r, ") and at most |P| = ", X.size());
    if (opt.halo < 2) fail("rom: the candidate halo must be at least 2 cells, got ", opt.halo);
    ranked = rank_samples(X, opt.sampling);
    slot.assign(X.size(), -1);

    Xn_particles = model.norm_X.apply(
        torch::from_blob(X.data()->data(), {int64_t(X.size()), 3}, torch::kFloat64)
            .to(torch::kFloat32));
    Xn_all = Xn_particles;
    all_points = fields.prepare(X);
    if (opt.linearize > 0 && opt.quadrature_per_cell > 0)
      fail("rom: --linearize and --quadrature do not combine (the tangent cache is per particle)");
    if (opt.linearize > 0) make_linearized_fields();
    sim = std::make_unique<Simulation>(std::move(scene));
    sim->particles() = Particles{};
    set_samples(sample_count_at(opt.sampling, 0, T));
    if (tracking()) start_tracking(F0, cfl_bound);

    if (!(opt.latent_prior >= 0 && std::isfinite(opt.latent_prior)))
      fail("rom: the latent prior's length must be a number of metres, 0 or more, got ",
           opt.latent_prior);
    if (model.trajectory_latents.defined()) make_latent_prior();
    if (opt.latent_prior > 0) {
      if (!prior)
        fail(
            "rom: the latent prior (--latent-prior, rom.latent_prior) needs the training runs' "
            "latents, and this model file has none (it was trained before nsf stored them): "
            "retrain it with nsf train, or run without the prior (--latent-prior 0)");
      opt.inversion.prior = prior.get();
      opt.inversion.prior_length = opt.latent_prior;
    }
    // ẑ_0: the encoder's latent of the rest state, refined on S so that step 1 starts from the
    // latent the inversion itself would pick; ẑ_{-1}: fitted to X − Δt·v⁰.
    GaussNewtonOptions fit{8, 1e-7, false};
    fit.prior = opt.inversion.prior;
    fit.prior_length = opt.inversion.prior_length;
    z = fields.encode(std::vector<Vec3>(X.begin(), X.begin() + np));
    std::vector<Vec3> target(S.size());
    for (size_t k = 0; k < S.size(); ++k) target[k] = X[S[k]];
    z = invert_deformation(model, Xn_S, target, z, fit).z;
    for (size_t k = 0; k < S.size(); ++k) target[k] = X[S[k]] - dt * v0[S[k]];
    z_prev = invert_deformation(model, Xn_S, target, z, fit).z;
  }

  // Each latent component's spread over the training latents: the unit in which the tangent
  // cache's radius and the latent prior's distance are measured.
  Eigen::VectorXd latent_spread() const {
    const torch::Tensor sd = model.norm_z.std.to(torch::kFloat64).contiguous();
    return Eigen::Map<const Eigen::VectorXd>(sd.data_ptr<double>(), sd.numel());
  }

  // The training runs' latents, in order of μ: the surface the latent prior holds the inversion
  // near, and what training_distance() measures from.
  void make_latent_prior() {
    const torch::Tensor t = model.trajectory_latents.to(torch::kFloat64).contiguous();
    const torch::Tensor m = model.trajectory_mu.to(torch::kFloat64).contiguous();
    const int64_t frames = t.size(1), r = t.size(2);
    const double *z = t.data_ptr<double>(), *mu_of = m.data_ptr<double>();
    std::vector<int64_t> order(size_t(t.size(0)));
    std::iota(order.begin(), order.end(), int64_t(0));
    std::stable_sort(order.begin(), order.end(),
                     [&](int64_t a, int64_t b) { return mu_of[a] < mu_of[b]; });
    std::vector<std::vector<Eigen::VectorXd>> runs;
    for (int64_t j : order) {
      runs.emplace_back();
      for (int64_t i = 0; i < frames; ++i)
        runs.back().push_back(Eigen::Map<const Eigen::VectorXd>(z + (j * frames + i) * r, r));
    }
    prior = std::make_unique<LatentPrior>(runs, latent_spread());
  }

  bool tracking() const {
    return opt.stress == StressSource::tracked || opt.affine == AffineSource::tracked;
  }

  // A tracked state is every particle's, so every particle must be a sample at every step
  // (then N = S = P and each one gets its G2P).
  void start_tracking(const std::vector<Mat3>& F0, double cfl_bound) {
    const char* what =
        opt.stress == StressSource::tracked ? "--stress tracked" : "--affine tracked";
    if (opt.sampling.count != int(np) || !opt.sampling.schedule.empty())
      fail("rom: ", what, " keeps every particle's own state, so every particle must be a sample: ",
           "use --samples ", np, " (|P|) and no sample schedule");
    if (opt.quadrature_per_cell > 0 || opt.linearize > 0 ||
        (opt.crom && opt.stress == StressSource::tracked))
      fail("rom: ", what, " does not combine with --quadrature, --linearize or --crom");
    // Unlike h's stress, the tracked one is the explicit engine's and shares its bound.
    if (opt.stress == StressSource::tracked && dt > cfl_bound * (1 + 1e-9))
      fail("rom: --stress tracked integrates the material explicitly, so the ROM step ", dt,
           " s must stay within the full-order CFL bound ", cfl_bound, " s: use --dt-ratio ",
           cfl_bound / sim->settings().dt, " or less");
    tracked.F = F0;
    tracked.mp = mat0;
    tracked.C.assign(np, Mat3::Zero());
    tracked.tau.resize(np);
    for (size_t p = 0; p < np; ++p) tracked.tau[p] = material_update(p, tracked.F[p]);
  }

  Mat3 material_update(size_t p, Mat3& F) {
    return sim->scene().materials[material[p]]->update(F, tracked.mp[p], dt);
  }

  // After G2P, which has advanced each particle's tracked F by its own velocity gradient.
  void advance_tracked(const Particles& P, const std::vector<uint32_t>& gather) {
    for (size_t k = 0; k < S.size(); ++k) {
      const uint32_t p = S[k];
      tracked.F[p] = P.F[gather[k]];
      tracked.tau[p] = material_update(p, tracked.F[p]);
      tracked.C[p] = P.C[gather[k]];
    }
  }

  void make_linearized_fields() {
    if (opt.crom || opt.affine == AffineSource::velocity)
      fail(
          "rom: --linearize expands the networks g, h and l; it does not combine with --crom or "
          "--affine velocity");
    const Eigen::VectorXd scale = latent_spread();
    const float mu_f = float(mu);
    NeuralModel* m = &model;
    lin_g = std::make_unique<LinearizedField>(
        [m](const torch::Tensor& Xn, const torch::Tensor& zz) { return m->deform(Xn, zz); }, 3,
        Xn_all, scale, opt.linearize);
    lin_h = std::make_unique<LinearizedField>(
        [m, mu_f](const torch::Tensor& Xn, const torch::Tensor& zz) {
          return m->stress(Xn, zz, torch::full({Xn.size(0), 1}, mu_f));
        },
        6, Xn_all, scale, opt.linearize);
    if (opt.affine == AffineSource::network)
      lin_l = std::make_unique<LinearizedField>(
          [m](const torch::Tensor& Xn, const torch::Tensor& zz) { return m->affine(Xn, zz); }, 9,
          Xn_all, scale, opt.linearize);
  }

  void set_samples(int count) {
    S.assign(ranked.begin(), ranked.begin() + count);
    Xn_S = Xn_all.index_select(0, index_tensor(S));
    K = CandidateSet(opt.halo);  // forces a refresh
    xK_last_valid = false;
    if (quad.ids.empty() || opt.quadrature_per_cell > 0) set_quadrature();
  }

  // The sample particles stay themselves in a thinned quadrature, so it follows S.
  void set_quadrature() {
    X.resize(np), material.resize(np), mat0.resize(np);
    const SimSettings& s = sim->settings();
    quad = thin_quadrature(X, mass, vol0, material, s.domain_lo, s.dx, opt.quadrature_per_cell, S);
    for (size_t j = 0; j < quad.merged_X.size(); ++j) {
      const uint32_t member = quad.merged_group[j];
      X.push_back(quad.merged_X[j]);
      material.push_back(material[member]);
      mat0.push_back(mat0[member]);
    }
    Xn_all = Xn_particles;
    if (thinned()) {
      const std::vector<Vec3>& merged = quad.merged_X;
      Xn_all = torch::cat(
          {Xn_particles,
           model.norm_X.apply(torch::from_blob(const_cast<double*>(merged.data()->data()),
                                               {int64_t(merged.size()), 3}, torch::kFloat64)
                                  .to(torch::kFloat32))});
      std::vector<Vec3> XQ(quad.ids.size());
      for (size_t k = 0; k < XQ.size(); ++k) XQ[k] = X[quad.ids[k]];
      quad_points = fields.prepare(XQ);
    }
    slot.assign(X.size(), -1);
  }

  bool thinned() const { return quad.thinned(); }

  // g at rows `ids` of the scene for one latent.
  void deform_rows(const std::vector<uint32_t>& ids, const Latent& zz, std::vector<Vec3>& x) {
    if (lin_g) {
      lin_g->prepare(ids, z);
      std::vector<double> out;
      lin_g->evaluate(ids, zz, out);
      rows_to_vec3(out, x);
      return;
    }
    torch::NoGradGuard no_grad;
    const int64_t m = int64_t(ids.size());
    to_vec3(model.deform(Xn_all.index_select(0, index_tensor(ids)),
                         latent_row(zz).expand({m, zz.size()})),
            x);
  }

  // g on K at ẑ_n and ẑ_{n−1}; the second is last step's first while K has not changed.
  void deform_candidates(std::vector<Vec3>& x, std::vector<Vec3>& xp) {
    ScopedTimer timer(times.inference);
    if (refreshed_at == n && !lin_g) {  // the refresh evaluated g at ẑ_n on K already
      x = K.refresh_positions();
      return deform_rows(K.ids(), z_prev, xp);
    }
    if (!xK_last_valid) return deform_pair(K.ids(), x, xp);
    xp.swap(xK_last);
    deform_rows(K.ids(), z, x);
  }

  // g at rows `ids` of the scene for ẑ_n and ẑ_{n−1} in one batched call.
  void deform_pair(const std::vector<uint32_t>& ids, std::vector<Vec3>& x, std::vector<Vec3>& xp) {
    if (lin_g) {
      deform_rows(ids, z, x);
      deform_rows(ids, z_prev, xp);
      return;
    }
    torch::NoGradGuard no_grad;
    const int64_t m = int64_t(ids.size());
    const torch::Tensor Xn = Xn_all.index_select(0, index_tensor(ids));
    const torch::Tensor zz =
        torch::cat({latent_row(z).expand({m, z.size()}), latent_row(z_prev).expand({m, z.size()})});
    const torch::Tensor out = model.deform(torch::cat({Xn, Xn}), zz);
    to_vec3(out.slice(0, 0, m), x);
    to_vec3(out.slice(0, m, 2 * m), xp);
  }

  const std::vector<Vec3>& all_positions() {
    if (cache_step != n) {
      fields.deform(all_points, z, x_cache);
      cache_step = n;
    }
    return x_cache;
  }

  void refresh() {
    ScopedTimer timer(times.refresh);
    xK_last_valid = false;
    if (!thinned()) {
      const std::vector<Vec3>& x = all_positions();
      std::vector<Vec3> xs(S.size());
      for (size_t k = 0; k < S.size(); ++k) xs[k] = x[S[k]];
      K.refresh(marks, x, xs);
    } else {
      // Only the quadrature points can join N, so only they need g.
      std::vector<Vec3> xq;
      fields.deform(quad_points, z, xq);
      std::vector<Vec3> xs(S.size());
      for (size_t k = 0; k < S.size(); ++k) {
        const auto at = std::lower_bound(quad.ids.begin(), quad.ids.end(), S[k]);
        xs[k] = xq[size_t(at - quad.ids.begin())];
      }
      K.refresh(marks, xq, xs, &quad.ids);
    }
    ++refreshes;
    refreshed_at = n;
  }

  // Positions xs of the particles ids must lie where the engine's stencils fit (its sort and
  // transfers index the grid unchecked), as the full-order engine's own guard requires.
  void check_finite_inside(const std::vector<Vec3>& xs, const std::vector<uint32_t>& ids,
                           const char* what) const {
    const SimSettings& s = sim->settings();
    for (size_t k = 0; k < xs.size(); ++k) {
      const Vec3& x = xs[k];
      const bool inside = x.allFinite() && (x - s.domain_lo).minCoeff() > 1.5 * dx &&
                          (s.domain_hi - x).minCoeff() > 1.5 * dx;
      if (!inside)
        fail("rom: ", what, " ",
             ids[k] < np ? "particle " + std::to_string(ids[k])
                         : "quadrature point " + std::to_string(ids[k] - np) +
                               " (merged particles of one cell)",
             " is at (", x[0], ", ", x[1], ", ", x[2], "), outside the grid, at step ", n,
             " (t = ", t,
             " s): the latent dynamics diverged. Try more sample particles (--samples), a smaller "
             "--dt-ratio, or a model trained longer.");
    }
  }

  void step() {
    const int want = sample_count_at(opt.sampling, t, T);
    if (size_t(want) != S.size()) set_samples(want);

    // (1) Inference on the candidates K ⊇ N, then N itself.
    std::vector<Vec3> xK, xK_prev;
    // Free when all particles' positions are known (output frames), unless thinned.
    if (K.empty() || (cache_step == n && !thinned())) refresh();
    deform_candidates(xK, xK_prev);
    if (K.stale(xK, dx)) {
      refresh();
      deform_candidates(xK, xK_prev);
    }
    std::vector<size_t> n_in_K;  // N as positions in K
    std::vector<Vec3> xs;        // S at ẑ_n
    {
      ScopedTimer timer(times.mpm);
      const auto& ids = K.ids();
      for (size_t k = 0; k < ids.size(); ++k) slot[ids[k]] = int32_t(k);
      xs.resize(S.size());
      for (size_t k = 0; k < S.size(); ++k) {
        if (slot[S[k]] < 0) fail("rom: internal error, sample particle ", S[k], " not a candidate");
        xs[k] = xK[slot[S[k]]];
      }
      for (uint32_t p : ids) slot[p] = -1;
      marks.clear();
      marks.mark_stencils(xs, 0);
      N.clear();
      for (size_t k = 0; k < ids.size(); ++k)
        if (marks.touches(xK[k])) n_in_K.push_back(k), N.push_back(ids[k]);
      // A diverging latent can carry a particle of N off the grid while its clamped stencil
      // still touches I's boundary nodes. S ⊆ N (a sample touches its own nodes), so this
      // checks the samples too.
      std::vector<Vec3> xN(N.size());
      for (size_t k = 0; k < N.size(); ++k) xN[k] = xK[n_in_K[k]];
      check_finite_inside(xN, N, "integration");
    }
    if (opt.verify_integration_set) verify_integration_set();
    sum_N += double(N.size());
    sum_K += double(K.ids().size());

    std::vector<Mat3> tau, C;
    {
      ScopedTimer timer(times.inference);
      stress_and_affine(N, true, tau, C);
    }

    // (2) One MPM step on N with the engine's own transfers; G2P for S only.
    std::vector<Vec3> xs_new(S.size());
    {
      ScopedTimer timer(times.mpm);
      Particles& P = sim->particles();
      const size_t m = N.size();
      P.X.resize(m), P.x.resize(m), P.v.resize(m), P.C.resize(m), P.F.resize(m), P.tau.resize(m);
      P.mass.resize(m), P.vol0.resize(m), P.mat.resize(m), P.material.resize(m);
      P.object.resize(m);
      for (size_t k = 0; k < m; ++k) {
        const uint32_t p = N[k];
        const size_t q = n_in_K[k];
        P.X[k] = X[p];
        P.x[k] = xK[q];
        P.v[k] = (xK[q] - xK_prev[q]) / dt;
        P.C[k] = C[k];
        P.F[k] = tracking() ? tracked.F[p] : Mat3::Identity();
        P.tau[k] = tau[k];
        P.mass[k] = quad.mass[p];
        P.vol0[k] = quad.vol0[p];
        P.mat[k] = mat0[p];
        P.material[k] = material[p];
        P.object[k] = 0;
        slot[p] = int32_t(k);
      }
      std::vector<uint32_t> gather(S.size());
      for (size_t k = 0; k < S.size(); ++k) gather[k] = uint32_t(slot[S[k]]);
      for (uint32_t p : N) slot[p] = -1;
      // The latent velocity field is smooth and g carries it exactly; the round trip through
      // the grid blurs it whenever l's C is off, and that loss recurs at every step, so a
      // ROM with small steps slows down (sand_small: δ 2.5 % at 1.0Δt, 3.5 % at 0.5Δt).
      std::vector<Vec3> smoothing(S.size(), Vec3::Zero());
      if (opt.flip > 0) {
        std::vector<Vec3> v_round_trip;
        sim->transfer_velocity(gather, v_round_trip);
        for (size_t k = 0; k < S.size(); ++k)
          smoothing[k] = opt.flip * (P.v[gather[k]] - v_round_trip[k]);
      }
      sim->transfer(dt, t, &gather);
      if (tracking()) advance_tracked(P, gather);
      for (size_t k = 0; k < S.size(); ++k) xs_new[k] = P.x[gather[k]] + dt * smoothing[k];
      check_finite_inside(xs_new, S, "sample");
    }

    // (3) Inversion for ẑ_{n+1}, warm-started from ẑ_n.
    {
      ScopedTimer timer(times.inversion);
      std::optional<ScopedBlasThreads> fit_threads;
      if (opt.inversion.threads > 0) fit_threads.emplace(opt.inversion.threads);
      const InversionResult res = invert_deformation(model, Xn_S, xs_new, z, opt.inversion);
      z_prev = z;
      z = res.z;
      last_residual = res.rms_residual;
      track_kinetic_energy(xs, xs_new, res);
      xK_last.swap(xK);
      xK_last_valid = true;
    }
    t += dt;
    ++n;
  }

  // τ and C on the rows `ids` at ẑ_n, from the sources the options name: h (or CROM's τ(∂g/∂X),
  // or the tracked state) and l (or the velocity field's gradient, the tracked C, or none).
  // `tangent_cache`: through --linearize's expansions when they exist, else the networks.
  void stress_and_affine(const std::vector<uint32_t>& ids, bool tangent_cache,
                         std::vector<Mat3>& tau, std::vector<Mat3>& C) {
    const int64_t m = int64_t(ids.size());
    tau.assign(ids.size(), Mat3::Zero());
    C.assign(ids.size(), Mat3::Zero());
    const bool cached_h = tangent_cache && lin_h, cached_l = tangent_cache && lin_l;
    const torch::Tensor Xn = Xn_all.index_select(0, index_tensor(ids));
    const torch::Tensor zz = latent_row(z).expand({m, z.size()});
    torch::Tensor F;  // ∂g/∂X at ẑ_n, when the stress or C needs it
    if (opt.crom || opt.affine == AffineSource::velocity) F = deformation_gradients(model, Xn, zz);
    if (opt.stress == StressSource::tracked) {
      for (int64_t k = 0; k < m; ++k) tau[k] = tracked.tau[ids[k]];
    } else if (opt.crom) {
      crom_stress(F, ids, tau);
    } else if (cached_h) {
      std::vector<double> out;
      lin_h->prepare(ids, z);
      lin_h->evaluate(ids, z, out);
      for (int64_t k = 0; k < m; ++k) tau[k] = symmetric_from6(&out[6 * k]);
    } else {
      torch::NoGradGuard no_grad;
      const torch::Tensor mus = torch::full({m, 1}, float(mu));
      const torch::Tensor h = model.stress(Xn, zz, mus).to(torch::kFloat64).contiguous();
      const double* hp = h.data_ptr<double>();
      for (int64_t k = 0; k < m; ++k) tau[k] = symmetric_from6(hp + 6 * k);
    }
    if (cached_l) {
      std::vector<double> out;
      lin_l->prepare(ids, z);
      lin_l->evaluate(ids, z, out);
      for (int64_t k = 0; k < m; ++k)
        C[k] = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(&out[9 * k]);
    } else if (opt.affine == AffineSource::network) {
      torch::NoGradGuard no_grad;
      const torch::Tensor l = model.affine(Xn, zz).to(torch::kFloat64).contiguous();
      const double* lp = l.data_ptr<double>();
      for (int64_t k = 0; k < m; ++k)
        C[k] = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(lp + 9 * k);
    } else if (opt.affine == AffineSource::tracked) {
      for (int64_t k = 0; k < m; ++k) C[k] = tracked.C[ids[k]];
    } else if (opt.affine == AffineSource::velocity) {
      const torch::Tensor F_prev =
          deformation_gradients(model, Xn, latent_row(z_prev).expand({m, z_prev.size()}));
      velocity_gradients(F, F_prev, dt, C);
    }
  }

  // The samples' kinetic energy after the MPM step, (x_S^{n+1} − x_S^n)/Δt, against what the
  // inversion keeps of it, (g(X_S, ẑ_{n+1}) − x_S^n)/Δt: velocity outside g's tangent is lost
  // at every step, and the loss compounds over a run's thousands of steps.
  void track_kinetic_energy(const std::vector<Vec3>& xs, const std::vector<Vec3>& xs_new,
                            const InversionResult& res) {
    std::vector<Vec3> taylor_fit;  // the Taylor step leaves g at its latent unevaluated
    if (res.fitted.empty()) {
      torch::NoGradGuard no_grad;
      to_vec3(model.deform(Xn_S, latent_row(res.z).expand({int64_t(S.size()), res.z.size()})),
              taylor_fit);
    }
    const std::vector<Vec3>& fitted = res.fitted.empty() ? taylor_fit : res.fitted;
    for (size_t k = 0; k < S.size(); ++k) {
      const double m = quad.mass[S[k]];
      energy_after_mpm += 0.5 * m * ((xs_new[k] - xs[k]) / dt).squaredNorm();
      energy_after_inversion += 0.5 * m * ((fitted[k] - xs[k]) / dt).squaredNorm();
    }
  }

  // CROM: τ = τ(F) with F = ∂g/∂X, through the scene's own constitutive models (each particle's
  // initial plastic state: the baseline has no plastic history).
  void crom_stress(const torch::Tensor& F, const std::vector<uint32_t>& ids,
                   std::vector<Mat3>& tau) {
    const int64_t m = F.size(0);
    const double* f = F.data_ptr<double>();
    const auto& materials = sim->scene().materials;
    for (int64_t k = 0; k < m; ++k) {
      Mat3 Fk = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(f + 9 * k);
      MaterialPoint mp = mat0[ids[k]];
      tau[k] = materials[material[ids[k]]]->update(Fk, mp, dt);
    }
  }

  void verify_integration_set() {
    // Brute force: g on every quadrature point, N by the definition, compared with the scheme's.
    std::vector<Vec3> x;
    fields.deform(thinned() ? quad_points : all_points, z, x);
    std::vector<uint32_t> ours = N;
    std::sort(ours.begin(), ours.end());
    for (uint32_t row : nsf::integration_particles(marks, x))
      if (!std::binary_search(ours.begin(), ours.end(), quad.ids[row])) ++misses;
  }
};

LatentStepper::LatentStepper(NeuralFields& fields, Scene scene, double mu,
                             const RomOptions& options)
    : impl_(std::make_unique<Impl>(fields, std::move(scene), mu, options)) {}
LatentStepper::~LatentStepper() = default;

void LatentStepper::step() {
  impl_->step();
}
void LatentStepper::advance_frame() {
  for (int i = 0; i < impl_->per_frame; ++i) impl_->step();
}
double LatentStepper::time() const {
  return impl_->t;
}
double LatentStepper::dt() const {
  return impl_->dt;
}
int LatentStepper::steps_per_frame() const {
  return impl_->per_frame;
}
long LatentStepper::step_count() const {
  return impl_->n;
}
const Latent& LatentStepper::latent() const {
  return impl_->z;
}
const Latent& LatentStepper::previous_latent() const {
  return impl_->z_prev;
}

void LatentStepper::state(const NeuralFields::Points& X, std::vector<Vec3>& x,
                          std::vector<Vec3>* v) const {
  impl_->fields.deform(X, impl_->z, x);
  if (!v) return;
  impl_->fields.deform(X, impl_->z_prev, *v);
  for (size_t k = 0; k < x.size(); ++k) (*v)[k] = (x[k] - (*v)[k]) / impl_->dt;
}

void LatentStepper::particle_state(std::vector<Vec3>& x, std::vector<Vec3>* v) {
  x = impl_->all_positions();
  if (!v) return;
  impl_->fields.deform(impl_->all_points, impl_->z_prev, *v);
  for (size_t k = 0; k < x.size(); ++k) (*v)[k] = (x[k] - (*v)[k]) / impl_->dt;
}

void LatentStepper::particle_fields(std::vector<Mat3>& tau, std::vector<Mat3>& C) {
  std::vector<uint32_t> ids(impl_->np);
  for (size_t p = 0; p < ids.size(); ++p) ids[p] = uint32_t(p);
  impl_->stress_and_affine(ids, false, tau, C);
}

size_t LatentStepper::particle_count() const {
  return impl_->np;
}
size_t LatentStepper::sample_count() const {
  return impl_->S.size();
}
const std::vector<uint32_t>& LatentStepper::samples() const {
  return impl_->S;
}
const std::vector<uint32_t>& LatentStepper::integration_particles() const {
  return impl_->N;
}
double LatentStepper::mean_integration_count() const {
  return impl_->n ? impl_->sum_N / double(impl_->n) : 0.0;
}
size_t LatentStepper::quadrature_count() const {
  return impl_->quad.ids.size();
}
double LatentStepper::mean_candidate_count() const {
  return impl_->n ? impl_->sum_K / double(impl_->n) : 0.0;
}
long LatentStepper::refreshes() const {
  return impl_->refreshes;
}
long LatentStepper::linearization_anchors() const {
  return impl_->lin_g ? impl_->lin_g->anchors() : 0;
}
long LatentStepper::integration_misses() const {
  return impl_->misses;
}
double LatentStepper::inversion_energy_kept() const {
  return impl_->energy_after_mpm > 0 ? impl_->energy_after_inversion / impl_->energy_after_mpm
                                     : 1.0;
}
double LatentStepper::training_distance() const {
  return impl_->prior ? std::sqrt(impl_->prior->distance2(impl_->z)) : -1.0;
}
double LatentStepper::last_inversion_residual() const {
  return impl_->last_residual;
}
const RomTimes& LatentStepper::times() const {
  return impl_->times;
}

}  // namespace nsf
