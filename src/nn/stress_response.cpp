#include "nn/stress_response.h"

#include <Eigen/Eigenvalues>
#include <algorithm>

#include "core/error.h"
#include "io/run_reader.h"
#include "nn/dataset.h"

namespace nsf {

StressResponse::StressResponse(const Dataset& data) {
  for (const SimulationFile& run : data.train()) {
    const RunReader reader(run.path);
    if (reader.scene_json().empty())
      fail(run.path, ": stores no scene, so the material's response is unknown");
    Scene s = build_scene(nlohmann::json::parse(reader.scene_json()));
    if (s.particles.size() != data.particle_count())
      fail(run.path, ": its stored scene builds ", s.particles.size(), " particles, the run has ",
           data.particle_count());
    for (const auto& m : s.materials)
      if (m->type() != "von_mises" && m->type() != "drucker_prager" && m->type() != "stvk_hencky")
        fail(run.path, ": material '", m->type(),
             "' is not Hencky-elastic; the stress response needs von_mises, drucker_prager or "
             "stvk_hencky");
    scenes_.push_back(std::move(s));
  }
}

Mat3 StressResponse::respond(size_t run, size_t p, const Mat3& tau, const Mat3& dF) const {
  const Scene& s = scenes_[run];
  MaterialPoint mp = s.particles.mat[p];
  const Eigen::SelfAdjointEigenSolver<Mat3> eig(tau);
  const Vec3 t = eig.eigenvalues();
  // Hencky: τ_i = 2μ ε_i + λ tr ε, so tr τ = (2μ + 3λ) tr ε.
  const double tr_eps = t.sum() / (2.0 * mp.mu + 3.0 * mp.lambda);
  const Vec3 eps = (t.array() - mp.lambda * tr_eps).matrix() / (2.0 * mp.mu);
  const Mat3& Q = eig.eigenvectors();
  Mat3 F = dF * (Q * eps.array().exp().matrix().asDiagonal() * Q.transpose());
  // von Mises' yield condition is ‖dev τ‖ ≤ τ_y: a point on it has τ_y = ‖dev τ‖ now.
  if (mp.yield_stress > 0) {
    const Mat3 dev = tau - Mat3::Identity() * (tau.trace() / 3.0);
    mp.yield_stress = std::max(mp.yield_stress, dev.norm());
  }
  return s.materials[s.particles.material[p]]->update(F, mp, s.settings.dt);
}

}  // namespace nsf
