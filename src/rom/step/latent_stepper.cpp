#include "rom/step/latent_stepper.h"
#include "rom/step/stepper_checks.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <optional>

#include "core/blas_threads.h"
#include "core/error.h"
#include "mpm/simulation.h"
#include "nn/latent_inversion.h"
#include "rom/fields/field_source.h"
#include "rom/inversion/rom_inversion.h"
#include "rom/step/integration_set.h"
#include "rom/step/quadrature.h"
#include "rom/step/rigid_frames.h"
#include "rom/step/rom_diverged.h"
#include "rom/step/sample_selection.h"
#include "rom/step/tracked_particles.h"

namespace nsf {

namespace {

// OpenMP on one thread while it lives, when `points` is below `threshold` (and K is known).
class OneThreadBelow {
 public:
  OneThreadBelow(size_t points, size_t threshold)
      : threads_(points > 0 && points < threshold ? omp_get_max_threads() : 0) {
    if (threads_ > 1) omp_set_num_threads(1);
  }
  ~OneThreadBelow() {
    if (threads_ > 1) omp_set_num_threads(threads_);
  }
  OneThreadBelow(const OneThreadBelow&) = delete;
  OneThreadBelow& operator=(const OneThreadBelow&) = delete;

 private:
  int threads_;
};

// The scene with the ROM's grid: Δx `factor` times the scene's, the particles unchanged.
Scene on_rom_grid(Scene scene, double factor) {
  if (!(factor >= 1)) fail("rom: the ROM grid's factor must be at least 1, got ", factor);
  scene.settings.dx *= factor;
  return scene;
}

}  // namespace

struct LatentStepper::Impl {
  StepperChecks checks;  // only a test turns them on (rom/step/stepper_checks.h)
  NeuralFields& fields;
  RomOptions opt;
  double mu;
  std::unique_ptr<Simulation> sim;  // its particles() hold N only, refilled every step
  // The points whose constant data (X, mass, volume, material, plastic state) sim's particles
  // hold, in order: while N stays the same list, only its changing state is handed over.
  std::vector<uint32_t> resident;
  // The step's x, v, τ and C on N, kept between steps so that they are not allocated anew; they
  // change places with sim's particle arrays (swap) rather than being copied into them.
  std::vector<Vec3> xN, vN;
  std::vector<Mat3> tauN, CN;
  // The fit of ẑ to the samples' positions, under the latent prior where one is on.
  std::unique_ptr<RomInversion> inversion;
  // Per particle of the scene, then per merged quadrature point (rom/step/quadrature.h): what the
  // ROM needs of the full particle set. mass and vol0 are the particles' own.
  size_t np = 0;  // |P|
  PointTable table;
  std::vector<double> mass, vol0;
  NeuralFields::Points all_points;

  std::vector<uint32_t> ranked, S;
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
  // The quadrature points that can join N (every particle unless thinned, rom/step/quadrature.h)
  // with their masses and volumes; when thinned, the points prepared for g.
  ThinnedQuadrature quad;
  NeuralFields::Points quad_points;
  // g(X, ẑ_n) on K from the last step: this step's g(X, ẑ_{n−1}) while K is unchanged.
  std::vector<Vec3> xK_last;
  bool xK_last_valid = false;
  long refreshed_at = -1;  // step of the last refresh: g(X, ẑ_n) on K is then known

  // The field sources (rom/fields/field_source.h), chosen once, and the tracked state they may
  // read.
  std::unique_ptr<TrackedParticles> tracked;
  std::unique_ptr<FieldContext> context;
  std::unique_ptr<DeformationSource> g;
  std::unique_ptr<PointFieldSource> stress, affine;
  std::unique_ptr<VelocitySource> velocity;
  std::vector<Vec3> xN_prev;
  std::unique_ptr<SampleDeformation> g_S;  // g and ∂g/∂ẑ on S, for the inversion
  // The objects that move in frames of their own (RomOptions::rigid_frames): z and z_prev then
  // carry each frame's θ and t after the model's latent.
  RigidFrames frames;
  mutable Latent z_model, z_prev_model;  // latent()'s and previous_latent()'s where they are on

  double sum_N = 0, sum_K = 0, last_residual = 0, last_courant = 0;
  double last_margin = std::numeric_limits<double>::infinity();
  double sample_condition = -1;  // of g's tangents on S, with QDEIM's samples
  double energy_after_mpm = 0, energy_after_inversion = 0;  // summed over steps, on S
  long refreshes = 0, misses = -1;  // misses: −1 until the brute-force check of N runs
  RomTimes times;

  Impl(NeuralFields& f, Scene scene, double mu_, const RomOptions& o)
      : fields(f),
        opt(o),
        mu(mu_),
        marks(scene.settings.domain_lo, scene.settings.dx,
              Grid(scene.settings.domain_lo, scene.settings.domain_hi, scene.settings.dx).dims()),
        K(o.halo) {
    const Particles& P = scene.particles;
    fields.check_scene(scene.name, P.X, "scene '" + scene.name + "'");
    table.particles = np = P.X.size();
    table.X = P.X, table.material = P.material, table.mat0 = P.mat;
    mass = P.mass, vol0 = P.vol0;
    const std::vector<Vec3> v0 = P.v;
    const std::vector<Mat3> F0 = P.F;
    double wave_speed = 0;
    const double cfl_bound = cfl_time_step_bound(scene, &wave_speed) *
                             (opt.cfl > 0 ? opt.cfl / scene.settings.cfl : 1.0);
    const SimSettings& s = scene.settings;
    const bool at_cfl = opt.dt_ratio == RomOptions::kDtRatioAtCfl;
    if (!(opt.dt_ratio > 0) && !at_cfl)
      fail("rom: the time-step ratio must be positive, got ", opt.dt_ratio);
    // A frame holds a whole number of ROM steps, at least one: a larger ratio was clamped
    // without a word.
    if (opt.dt_ratio > s.substeps)
      fail("rom: the time-step ratio (--dt-ratio or the scene's rom.dt_ratio) ", opt.dt_ratio,
           " is more than the scene's ", s.substeps,
           " steps per frame; at most that (one ROM step per frame)");
    // Not capped at the full-order CFL bound: the stress on N comes from h at ẑ, not from F
    // integrated over the step, so the grid's elastic waves do not set the ROM's stability
    // limit (sand_paper runs at 4Δt, 3.7 times the bound;
    // docs/experiments/2026-11-25-larger-rom-steps.md).
    // At the CFL bound: the fewest whole steps per frame that keep within it, the fastest
    // particle's start speed added to the wave's (cfl·Δx / (c + |v|), MPM's usual bound): a throw
    // or an inflow crosses cells too, and a ROM step at the elastic bound alone let a faster
    // inflow leave the grid (docs/experiments/2026-11-30-step-at-the-cfl-bound.md).
    double v_max = 0;
    for (const Vec3& v : v0) v_max = std::max(v_max, v.norm());
    const double step_bound = cfl_bound * wave_speed / (wave_speed + v_max);
    per_frame = at_cfl ? std::max(1, int(std::ceil(s.substeps * s.dt / step_bound * (1 - 1e-9))))
                       : std::max(1, int(std::lround(s.substeps / opt.dt_ratio)));
    dt = s.substeps * s.dt / per_frame;
    T = s.frames * s.substeps * s.dt;
    dx = s.dx;
    const int r = fields.latent_dim();
    const int min_samples = (r + 2) / 3;
    if (opt.sampling.count < min_samples || size_t(opt.sampling.count) > np)
      fail("rom: |S| = ", opt.sampling.count, " sample particles is out of range: need at least ",
           min_samples, " (r/3 for r = ", r, ") and at most |P| = ", np);
    if (opt.halo < 2) fail("rom: the candidate halo must be at least 2 cells, got ", opt.halo);
    ranked = rank_samples(table.X, opt.sampling);
    if (opt.sampling.mode == "qdeim") ranked = qdeim_ranking(ranked);
    slot.assign(np, -1);
    all_points = fields.prepare(table.X);
    frames = make_rigid_frames(r, opt.rigid_frames, P.X, mass, P.object);
    sim = std::make_unique<Simulation>(std::move(scene));
    sim->particles() = Particles{};
    make_sources(F0);
    set_samples(sample_count_at(opt.sampling, 0, T));
    tracked->check(cfl_bound);

    inversion = std::make_unique<RomInversion>(fields.record(), opt.inversion, opt.latent_prior,
                                               frames.dim() - r);
    // ẑ_0: the encoder's latent of the rest state, refined on S so that step 1 starts from the
    // latent the inversion itself would pick; ẑ_{-1}: fitted to X − Δt·v⁰.
    z = frames.augment(
        fields.rest_latent(std::vector<Vec3>(table.X.begin(), table.X.begin() + np)));
    std::vector<Vec3> target(S.size());
    for (size_t k = 0; k < S.size(); ++k) target[k] = table.X[S[k]];
    z = inversion->fit_initial(*g_S, target, z);
    for (size_t k = 0; k < S.size(); ++k) target[k] = table.X[S[k]] - dt * v0[S[k]];
    z_prev = inversion->fit_initial(*g_S, target, z);
  }

  // QDEIM's particles on g's tangent directions first, then `fill` (a random ranking): the
  // tangents ∂g/∂ẑ of every particle at the rest state's latent and at up to kTangentLatents of
  // the training runs' latents, whose leading left singular vectors QDEIM picks rows of
  // (rom/step/sample_selection.h). Their conditioning on the first |S| is kept for the diagnostics.
  std::vector<uint32_t> qdeim_ranking(const std::vector<uint32_t>& fill) {
    constexpr int64_t kTangentLatents = 8;
    std::vector<uint32_t> all(np);
    std::iota(all.begin(), all.end(), 0u);
    const std::vector<Vec3> X(table.X.begin(), table.X.begin() + np);
    std::unique_ptr<SampleDeformation> g_all = fields.sample_deformation(X, all);
    std::vector<Latent> at = {fields.rest_latent(X)};
    const auto& runs = fields.record().trajectory_latents;
    if (!runs.empty()) {
      const int64_t frames = int64_t(runs[0].size()), total = int64_t(runs.size()) * frames;
      const int64_t count = std::min<int64_t>(kTangentLatents, total);
      for (int64_t k = 0; k < count; ++k) {
        const int64_t i = (k * total) / count;  // spread over runs and frames
        at.push_back(runs[size_t(i / frames)][size_t(i % frames)]);
      }
    }
    const int64_t r = fields.latent_dim();
    Eigen::MatrixXd A(3 * int64_t(np), r * int64_t(at.size())), J;
    std::vector<Vec3> g;
    for (size_t k = 0; k < at.size(); ++k) {
      g_all->jacobian(at[k], J, g);
      A.middleCols(r * int64_t(k), r) = J;
    }
    const Eigen::MatrixXd U = leading_left_singular_vectors(A, 1 - 1e-6);
    std::vector<uint32_t> out = qdeim_particles(U, fill);
    out.resize(std::min(out.size(), size_t(opt.sampling.count)));
    sample_condition = restricted_condition(U, out);
    return out;
  }

  // The sources the options name, for this model's decoders.
  void make_sources(const std::vector<Mat3>& F0) {
    tracked = std::make_unique<TrackedParticles>(F0, table.mat0, table.material,
                                                 sim->scene().materials, dt);
    context = std::make_unique<FieldContext>(
        FieldContext{fields, table, sim->scene().materials, mu, dt, tracked.get()});
    const FieldChoice c = opt.resolved_fields(fields.bases() ? "basis" : "network");
    g = make_deformation_source(c.deformation, *context);
    stress = make_point_field_source(FieldRole::stress, c.stress, *context);
    affine = make_point_field_source(FieldRole::affine, c.affine, *context);
    if (frames.on()) {
      g = in_rigid_frames(std::move(g), frames);
      stress = in_rigid_frames(std::move(stress), frames, c.stress != "tracked");
      affine = in_rigid_frames(std::move(affine), frames, c.affine != "tracked");
    }
    velocity = make_velocity_source(c.velocity, *context);
  }

  void set_samples(int count) {
    S.assign(ranked.begin(), ranked.begin() + count);
    K = CandidateSet(opt.halo);  // forces a refresh
    xK_last_valid = false;
    // The sample particles stay themselves in a thinned quadrature, so it follows S; but the
    // tracked state's points keep their history through the run, so there the first S's
    // quadrature stays (a schedule's S is a prefix of it, never larger: every later sample is still
    // a point of its own, and the dropped ones go on as such).
    if (quad.ids.empty() || (opt.quadrature_per_cell > 0 && !tracked->active())) set_quadrature();
    g_S = g->samples(S);
  }

  void set_quadrature() {
    const bool had_merged = table.X.size() > np;
    table.X.resize(np), table.material.resize(np), table.mat0.resize(np);
    const SimSettings& s = sim->settings();
    quad = thin_quadrature(table.X, mass, vol0, table.material, s.domain_lo, s.dx,
                           opt.quadrature_per_cell, S);
    for (size_t j = 0; j < quad.merged_X.size(); ++j) {
      const uint32_t member = quad.merged_group[j];
      table.X.push_back(quad.merged_X[j]);
      table.material.push_back(table.material[member]);
      table.mat0.push_back(merged_material(quad.merged_members[j], member, table.mat0));
    }
    table.merged_members = quad.merged_members;
    if (frames.on()) frames.extend(np, quad.merged_group);
    tracked->set_points(table);
    resident.clear();  // a merged point's id may now stand for another group
    if (thinned()) {
      std::vector<Vec3> XQ(quad.ids.size());
      for (size_t k = 0; k < XQ.size(); ++k) XQ[k] = table.X[quad.ids[k]];
      quad_points = fields.prepare(XQ);
    }
    if (thinned() || had_merged) {
      g->set_points();
      stress->set_points();
      affine->set_points();
    }
    slot.assign(table.X.size(), -1);
  }

  bool thinned() const { return quad.thinned(); }

  // g on K at ẑ_n and ẑ_{n−1}; the second is last step's first while K has not changed.
  void deform_candidates(std::vector<Vec3>& x, std::vector<Vec3>& xp) {
    ScopedTimer timer(times.inference);
    if (refreshed_at == n && g->exact()) {  // the refresh evaluated g at ẑ_n on K already
      x = K.refresh_positions();
      return g->positions(K.ids(), z_prev, z, xp);
    }
    if (!xK_last_valid) return g->positions_pair(K.ids(), {z, z_prev}, x, xp);
    xp.swap(xK_last);
    g->positions(K.ids(), z, z, x);
  }

  const std::vector<Vec3>& all_positions() {
    if (cache_step != n) {
      fields.deform(all_points, frames.model(z), x_cache);
      frames.apply(nullptr, z, x_cache);
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
      fields.deform(quad_points, frames.model(z), xq);
      frames.apply(&quad.ids, z, xq);
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

  // Cells between the points xs and the nearest place where a stencil no longer fits (1.5 Δx
  // inside a domain face); negative outside.
  double grid_margin(const std::vector<Vec3>& xs) const {
    const SimSettings& s = sim->settings();
    double margin = std::numeric_limits<double>::infinity();
    for (const Vec3& x : xs)
      margin =
          std::min(margin, std::min((x - s.domain_lo).minCoeff(), (s.domain_hi - x).minCoeff()));
    return margin / dx - 1.5;
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
        fail_diverged(
            "rom: ", what, " ",
            ids[k] < np ? "particle " + std::to_string(ids[k])
                        : "quadrature point " + std::to_string(ids[k] - np) +
                              " (merged particles of one cell)",
            " is at (", x[0], ", ", x[1], ", ", x[2], "), outside the grid, at step ", n,
            " (t = ", t,
            " s): the latent dynamics diverged. Try more sample particles (--samples), a smaller "
            "--dt-ratio, or a model trained longer.");
    }
  }

  // One step of §5: (1) infer x, v on N and τ, C there; (2) one MPM step on N, G2P for S;
  // (3) invert g on S for ẑ_{n+1}.
  void step() {
    const int want = sample_count_at(opt.sampling, t, T);
    if (size_t(want) != S.size()) set_samples(want);
    // A step over fewer candidates than opt.serial_below_points runs on one thread: its loops are
    // too small for a second thread to pay for waking up (metal_small on 2 threads: 0.66 s against
    // 1.08 s with one point per cell, 1.97 s against 2.46 s with every particle; docs/ROM.md).
    OneThreadBelow serial(K.empty() ? 0 : K.ids().size(), opt.serial_below_points);

    std::vector<Vec3> xs;  // S at ẑ_n
    infer_positions(xN, vN, xs);
    {
      ScopedTimer timer(times.inference);
      stress->evaluate(N, {z, z_prev}, true, tauN);
      affine->evaluate(N, {z, z_prev}, true, CN);
    }
    std::vector<Vec3> xs_new;
    mpm_on_integration_points(xs_new);
    invert(xs, xs_new);
    t += dt;
    ++n;
  }

  // (1) g on the candidates K ⊇ N, then N itself: the integration points whose stencils touch the
  // nodes I of the samples' stencils (§5.4). Positions and velocities on N.
  void infer_positions(std::vector<Vec3>& xN, std::vector<Vec3>& vN, std::vector<Vec3>& xs) {
    std::vector<Vec3> xK, xK_prev;
    // Free when all particles' positions are known (output frames), unless thinned.
    if (K.empty() || (cache_step == n && !thinned())) refresh();
    deform_candidates(xK, xK_prev);
    if (K.stale(xK, dx)) {
      refresh();
      deform_candidates(xK, xK_prev);
    }
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
      xN.clear(), xN_prev.clear();
      for (size_t k = 0; k < ids.size(); ++k)
        if (marks.touches(xK[k])) {
          N.push_back(ids[k]);
          xN.push_back(xK[k]);
          xN_prev.push_back(xK_prev[k]);
        }
      velocity->evaluate(N, xN, xN_prev, vN);
      double vmax = 0;
      for (const Vec3& v : vN) vmax = std::max(vmax, v.norm());
      last_courant = vmax * dt / dx;
      last_margin = grid_margin(xN);
      // A diverging latent can carry a particle of N off the grid while its clamped stencil
      // still touches I's boundary nodes. S ⊆ N (a sample touches its own nodes), so this
      // checks the samples too.
      check_finite_inside(xN, N, "integration");
    }
    if (checks.verify_integration_set) verify_integration_set();
    sum_N += double(N.size());
    sum_K += double(K.ids().size());
    xK_last.swap(xK);  // g(X, ẑ_n) on K: next step's g(X, ẑ_{n−1}) if K stays
  }

  // N's constant data into sim's particles, when N is not the list they already hold.
  void make_resident() {
    if (N == resident && !checks.refill_constant_data) return;
    Particles& P = sim->particles();
    const size_t m = N.size();
    P.X.resize(m), P.F.resize(m), P.mass.resize(m), P.vol0.resize(m), P.mat.resize(m);
    P.material.resize(m), P.object.assign(m, 0);
    for (size_t k = 0; k < m; ++k) {
      const uint32_t p = N[k];
      P.X[k] = table.X[p];
      P.F[k] = Mat3::Identity();
      P.mass[k] = quad.mass[p];
      P.vol0[k] = quad.vol0[p];
      P.mat[k] = table.mat0[p];
      P.material[k] = table.material[p];
    }
    resident = N;
  }

  // (2) One MPM step on N with the engine's own transfers; G2P for S only (for all of N with the
  // tracked state). Takes the step's xN, vN, tauN and CN (they change places with sim's particle
  // arrays).
  void mpm_on_integration_points(std::vector<Vec3>& xs_new) {
    ScopedTimer timer(times.mpm);
    make_resident();
    Particles& P = sim->particles();
    const size_t m = N.size();
    if (xN.size() != m || vN.size() != m || tauN.size() != m || CN.size() != m)
      fail("rom: internal error, the state on N has the wrong size");
    P.x.swap(xN), P.v.swap(vN), P.tau.swap(tauN), P.C.swap(CN);
    for (size_t k = 0; k < m; ++k) slot[N[k]] = int32_t(k);
    std::vector<uint32_t> gather(S.size());
    for (size_t k = 0; k < S.size(); ++k) gather[k] = uint32_t(slot[S[k]]);
    for (uint32_t p : N) slot[p] = -1;
    // G2P for S, or, with a tracked source, for every point of N, each with its own F (else the
    // identity: only the samples' positions are read).
    std::vector<uint32_t> all_rows;
    if (tracked->active()) {
      all_rows.resize(m);
      std::iota(all_rows.begin(), all_rows.end(), 0u);
      for (size_t k = 0; k < m; ++k) P.F[k] = tracked->F(N[k]);
    } else {
      for (uint32_t k : gather) P.F[k] = Mat3::Identity();
    }
    sim->transfer(dt, t, tracked->active() ? &all_rows : &gather);
    if (tracked->active()) tracked->advance(N, P, all_rows);
    xs_new.resize(S.size());
    for (size_t k = 0; k < S.size(); ++k) xs_new[k] = P.x[gather[k]];
    check_finite_inside(xs_new, S, "sample");
  }

  // (3) Inversion for ẑ_{n+1}, warm-started from ẑ_n.
  void invert(const std::vector<Vec3>& xs, const std::vector<Vec3>& xs_new) {
    ScopedTimer timer(times.inversion);
    std::optional<ScopedBlasThreads> fit_threads;
    if (opt.inversion.threads > 0) fit_threads.emplace(opt.inversion.threads);
    const InversionResult res = inversion->fit_step(*g_S, xs_new, z, n, t);
    z_prev = z;
    z = res.z;
    last_residual = res.rms_residual;
    track_kinetic_energy(xs, xs_new, res);
    xK_last_valid = true;
  }

  // The samples' kinetic energy after the MPM step, (x_S^{n+1} − x_S^n)/Δt, against what the
  // inversion keeps of it, (g(X_S, ẑ_{n+1}) − x_S^n)/Δt: velocity outside g's tangent is lost
  // at every step, and the loss compounds over a run's thousands of steps.
  void track_kinetic_energy(const std::vector<Vec3>& xs, const std::vector<Vec3>& xs_new,
                            const InversionResult& res) {
    std::vector<Vec3> taylor_fit;  // the Taylor step leaves g at its latent unevaluated
    if (res.fitted.empty()) g_S->evaluate(res.z, taylor_fit);
    const std::vector<Vec3>& fitted = res.fitted.empty() ? taylor_fit : res.fitted;
    for (size_t k = 0; k < S.size(); ++k) {
      const double m = quad.mass[S[k]];
      energy_after_mpm += 0.5 * m * ((xs_new[k] - xs[k]) / dt).squaredNorm();
      energy_after_inversion += 0.5 * m * ((fitted[k] - xs[k]) / dt).squaredNorm();
    }
  }

  // Every cache of g at a latent goes: the candidates are found again from all positions.
  void forget_cached_positions() {
    cache_step = -1;
    xK_last_valid = false;
    refreshed_at = -1;
    K = CandidateSet(opt.halo);
  }

  // The step's length, in every part that reads it.
  void set_dt(double step) {
    dt = step;
    context->dt = step;
    tracked->set_dt(step);
  }

  void verify_integration_set() {
    // Brute force: g on every quadrature point, N by the definition, compared with the scheme's.
    std::vector<Vec3> x;
    fields.deform(thinned() ? quad_points : all_points, frames.model(z), x);
    frames.apply(thinned() ? &quad.ids : nullptr, z, x);
    std::vector<uint32_t> ours = N;
    std::sort(ours.begin(), ours.end());
    misses = std::max(misses, 0L);
    for (uint32_t row : nsf::integration_particles(marks, x))
      if (!std::binary_search(ours.begin(), ours.end(), quad.ids[row])) ++misses;
  }
};

LatentStepper::LatentStepper(NeuralFields& fields, Scene scene, double mu,
                             const RomOptions& options)
    : impl_(std::make_unique<Impl>(fields, on_rom_grid(std::move(scene), options.grid_factor), mu,
                                   options)) {}
LatentStepper::~LatentStepper() = default;

void LatentStepper::step() {
  impl_->step();
}
LatentStepper::Checkpoint LatentStepper::checkpoint() {
  Impl& m = *impl_;
  if (m.tracked->active()) m.tracked->mark();
  return {m.z, m.z_prev, m.t, m.n};
}
void LatentStepper::restore(const Checkpoint& c) {
  Impl& m = *impl_;
  m.z = c.z, m.z_prev = c.z_prev, m.t = c.t, m.n = c.n;
  if (m.tracked->active()) m.tracked->rollback();
  m.forget_cached_positions();
}
void LatentStepper::step_split(int parts) {
  if (parts < 1) fail("rom: a step splits into one part or more, got ", parts);
  Impl& m = *impl_;
  const double t0 = m.t, full = m.dt;
  const long n0 = m.n;
  m.z_prev = m.z - (m.z - m.z_prev) / parts;
  m.forget_cached_positions();  // g at the old ẑ_{n−1} among them
  m.set_dt(full / parts);
  try {
    for (int i = 0; i < parts; ++i) m.step();
  } catch (...) {
    m.set_dt(full);
    throw;
  }
  m.set_dt(full);
  m.z_prev = m.z - parts * (m.z - m.z_prev);
  m.t = t0 + full, m.n = n0 + 1;
  m.forget_cached_positions();  // they are keyed by a step count the substeps ran past
}
LatentStepper::Signals LatentStepper::signals() const {
  return {impl_->last_residual / impl_->dx, impl_->last_courant, impl_->last_margin};
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
  if (!impl_->frames.on()) return impl_->z;
  impl_->z_model = impl_->frames.model(impl_->z);
  return impl_->z_model;
}
const GaussNewtonOptions& LatentStepper::inversion_options() const {
  return impl_->inversion->options();
}
const RigidFrames& LatentStepper::rigid_frames() const {
  return impl_->frames;
}
std::vector<std::unique_ptr<Collider>>& LatentStepper::colliders() {
  return impl_->sim->colliders();
}
const TrainingBox& LatentStepper::training_box() const {
  return impl_->fields.training_box();
}
double LatentStepper::grid_dx() const {
  return impl_->dx;
}
const Latent& LatentStepper::previous_latent() const {
  if (!impl_->frames.on()) return impl_->z_prev;
  impl_->z_prev_model = impl_->frames.model(impl_->z_prev);
  return impl_->z_prev_model;
}

void LatentStepper::state(const NeuralFields::Points& X, const std::vector<uint16_t>& object,
                          std::vector<Vec3>& x, std::vector<Vec3>* v) const {
  const RigidFrames& frames = impl_->frames;
  impl_->fields.deform(X, frames.model(impl_->z), x);
  frames.apply_to_objects(object, impl_->z, x);
  if (!v) return;
  impl_->fields.deform(X, frames.model(impl_->z_prev), *v);
  frames.apply_to_objects(object, impl_->z_prev, *v);
  for (size_t k = 0; k < x.size(); ++k) (*v)[k] = (x[k] - (*v)[k]) / impl_->dt;
}

std::vector<int> LatentStepper::particle_rigid_frames() const {
  if (!impl_->frames.on()) return {};
  return {impl_->frames.frame.begin(), impl_->frames.frame.begin() + std::ptrdiff_t(impl_->np)};
}
void LatentStepper::rigid_frame_pose(int f, Mat3& R, Vec3& offset) const {
  if (f < 0 || f >= impl_->frames.frames)
    fail("rom: rigid frame ", f, " of ", impl_->frames.frames);
  impl_->frames.pose(impl_->z, f, R, offset);
}

void LatentStepper::particle_state(std::vector<Vec3>& x, std::vector<Vec3>* v) {
  x = impl_->all_positions();
  if (!v) return;
  impl_->fields.deform(impl_->all_points, impl_->frames.model(impl_->z_prev), *v);
  impl_->frames.apply(nullptr, impl_->z_prev, *v);
  for (size_t k = 0; k < x.size(); ++k) (*v)[k] = (x[k] - (*v)[k]) / impl_->dt;
}

void LatentStepper::particle_fields(std::vector<Mat3>& tau, std::vector<Mat3>& C) {
  std::vector<uint32_t> ids(impl_->np);
  for (size_t p = 0; p < ids.size(); ++p) ids[p] = uint32_t(p);
  impl_->stress->evaluate(ids, {impl_->z, impl_->z_prev}, false, tau);
  impl_->affine->evaluate(ids, {impl_->z, impl_->z_prev}, false, C);
}
void LatentStepper::particle_stress(std::vector<Mat3>& tau) {
  std::vector<uint32_t> ids(impl_->np);
  for (size_t p = 0; p < ids.size(); ++p) ids[p] = uint32_t(p);
  impl_->stress->evaluate(ids, {impl_->z, impl_->z_prev}, false, tau);
}
void LatentStepper::particle_affine(std::vector<Mat3>& C) {
  std::vector<uint32_t> ids(impl_->np);
  for (size_t p = 0; p < ids.size(); ++p) ids[p] = uint32_t(p);
  impl_->affine->evaluate(ids, {impl_->z, impl_->z_prev}, false, C);
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

RomDiagnostics LatentStepper::diagnostics() const {
  const Impl& m = *impl_;
  RomDiagnostics d;
  d.times = m.times;
  d.field_sources = m.g->describe() + ", " + m.stress->describe() + ", " + m.affine->describe();
  if (!m.velocity->describe().empty()) d.field_sources += ", " + m.velocity->describe();
  d.mean_N = m.n ? m.sum_N / double(m.n) : 0.0;
  d.mean_K = m.n ? m.sum_K / double(m.n) : 0.0;
  d.quadrature_points = m.quad.ids.size();
  d.refreshes = m.refreshes;
  d.integration_misses = m.misses;
  d.last_residual = m.last_residual;
  d.sample_condition = m.sample_condition;
  d.training_distance = m.inversion->training_distance(m.frames.model(m.z));
  d.energy_kept = m.energy_after_mpm > 0 ? m.energy_after_inversion / m.energy_after_mpm : 1.0;
  d.courant = m.last_courant;
  return d;
}

void set_stepper_checks(LatentStepper& stepper, const StepperChecks& checks) {
  stepper.impl_->checks = checks;
}

}  // namespace nsf
