// Guards that stop a run which has gone wrong, with a message saying what to change.
#include <cmath>
#include <sstream>

#include "core/error.h"
#include "mpm/simulation.h"

namespace nsf {

namespace {
bool finite(const Vec3& a) {
  return std::isfinite(a[0]) && std::isfinite(a[1]) && std::isfinite(a[2]);
}
}  // namespace

void Simulation::check_particles() const {
  const Particles& P = scene_.particles;
  const SimSettings& s = scene_.settings;
  // A particle's 3x3x3 stencil must stay on the grid: one cell of margin on each side.
  const Vec3 lo = s.domain_lo + Vec3::Constant(s.dx);
  const Vec3 hi = grid_.lo() + (grid_.dims().cast<double>() - Vec3::Constant(2.0)) * s.dx;
  const double vmax = s.cfl * s.dx / s.dt;
  const long np = long(P.size());
  long bad = -1;
#pragma omp parallel for schedule(static) reduction(max : bad)
  for (long p = 0; p < np; ++p) {
    if (bad >= 0) continue;
    bool ok = finite(P.x[p]) && finite(P.v[p]) && P.F[p].allFinite() && P.tau[p].allFinite();
    ok = ok && (P.x[p].array() >= lo.array()).all() && (P.x[p].array() <= hi.array()).all();
    ok = ok && P.v[p].norm() <= vmax;
    if (!ok) bad = p;
  }
  if (bad < 0) return;
  const size_t p = static_cast<size_t>(bad);
  const Vec3& x = P.x[p];
  const double t = time_;
  std::ostringstream pos;
  pos << "(" << x[0] << ", " << x[1] << ", " << x[2] << ")";
  if (!finite(P.x[p]) || !finite(P.v[p]) || !P.F[p].allFinite() || !P.tau[p].allFinite())
    fail("simulation blew up at t = ", t, " (step ", steps_, "): particle ", p,
         " has a non-finite position, velocity, F or stress (position ", pos.str(),
         "). Lower simulation.dt, or check the material parameters.");
  if (!((x.array() >= lo.array()).all() && (x.array() <= hi.array()).all()))
    fail("simulation: particle ", p, " left the domain at t = ", t, " (step ", steps_,
         "), position ", pos.str(), "; the domain is [", s.domain_lo.transpose(), "] to [",
         s.domain_hi.transpose(),
         "]. Enlarge simulation.domain_lo/domain_hi, add a collider, "
         "or lower the velocities.");
  fail("simulation: particle ", p, " moves at ", P.v[p].norm(), " m/s at t = ", t, " (step ",
       steps_, "), position ", pos.str(), ", over the CFL limit ", vmax,
       " m/s (cfl·dx/dt). Lower simulation.dt or the initial velocities.");
}

}  // namespace nsf
