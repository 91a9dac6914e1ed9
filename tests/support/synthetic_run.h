#pragma once
// Small hand-made runs for the render and export tests, written with RunWriter in milliseconds
// instead of simulated: two blocks (objects 0 and 1, materials 0 and 1) sliding along +x, with a
// velocity, stress and deformation gradient that differ per particle and per frame so that a
// swapped index or component shows up.
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "cli_runner.h"
#include "io/run_writer.h"
#include "mpm/particles.h"
#include "mpm/scene/scene.h"

namespace nsf::testing {

inline const char* kSyntheticScene = R"({
  "name": "two_blocks",
  "simulation": {"domain_lo": [0, 0, 0], "domain_hi": [1, 1, 1], "dx": 0.03125, "dt": 1e-3, "ppc": 1},
  "objects": [
    {"shape": {"type": "box", "min": [0.2, 0.1, 0.4], "max": [0.4, 0.3, 0.6]},
     "material": {"type": "fixed_corotated", "E": 1e4, "nu": 0.3}},
    {"shape": {"type": "sphere", "center": [0.6, 0.2, 0.5], "radius": 0.1},
     "material": {"type": "drucker_prager", "E": 1e4, "nu": 0.3, "friction_angle": 30}}
  ],
  "colliders": [{"type": "plane", "point": [0, 0.1, 0], "normal": [0, 1, 0]}]
})";

inline void set_synthetic_frame(Particles& ps, int frame) {
  for (size_t p = 0; p < ps.size(); ++p) {
    const double s = 0.01 * static_cast<double>(p) + frame;
    ps.x[p] = ps.X[p] + Vec3(0.04 * frame, 0, 0);
    ps.v[p] = Vec3(0.4 + 0.1 * std::sin(s), 0.05 * std::cos(s), -0.02 * frame);
    Mat3 a;
    a << 1 + s, 2, 3, 4, 5 + s, 6, 7, 8, 9 - s;
    ps.tau[p] = 100.0 * (a + a.transpose());
    ps.F[p] = Mat3::Identity() + 0.001 * a;
    ps.C[p] = 0.5 * a;
  }
}

inline Particles synthetic_particles() {
  Particles ps;
  const double h = 0.03125;
  for (int o = 0; o < 2; ++o)
    for (int i = 0; i < 6; ++i)
      for (int j = 0; j < 6; ++j)
        for (int k = 0; k < 6; ++k) {
          const Vec3 X = Vec3(0.2 + 0.4 * o, 0.12, 0.4) + h * Vec3(i, j, k);
          ps.add(X, Vec3::Zero(), 1e-3, h * h * h, MaterialPoint{}, static_cast<uint16_t>(o),
                 static_cast<uint16_t>(o));
        }
  return ps;
}

// Writes `frames` frames at times 0, 0.05, ... and returns the particles of the last one.
inline void write_synthetic_run(const std::string& path, int frames,
                                const std::string& scene_json = kSyntheticScene) {
  Particles ps = synthetic_particles();
  SimSettings s;
  s.dx = 0.03125;
  s.dt = 1e-3;
  s.substeps = 50;
  RunWriter w(path, ps, s, "two_blocks", scene_json);
  for (int f = 0; f < frames; ++f) {
    set_synthetic_frame(ps, f);
    w.write_frame(ps, 0.05 * f);
  }
  w.finish();
}

inline bool ffmpeg_available() {
  return std::system("ffmpeg -version > /dev/null 2>&1") == 0;
}

}  // namespace nsf::testing
