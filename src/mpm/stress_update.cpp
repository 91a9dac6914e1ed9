// Return map and Kirchhoff stress (§3.3 step 3): F^E = returnMap(F^trial), τ = τ(F^E).
#include "mpm/simulation.h"

namespace nsf {

void Simulation::update_stress() {
  ScopedTimer timer(times_.stress);
  Particles& P = scene_.particles;
  const double dt = scene_.settings.dt;
  const long np = long(P.size());
  const auto& materials = scene_.materials;
#pragma omp parallel for schedule(static)
  for (long p = 0; p < np; ++p) P.tau[p] = materials[P.material[p]]->update(P.F[p], P.mat[p], dt);
}

}  // namespace nsf
