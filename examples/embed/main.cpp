// Embedding nsf: load a trained model and its scene, step the reduced-order model frame by
// frame, move a collider from the host each frame, and read the positions into a buffer the host
// owns. Usage: embed MODEL SCENE MU [LIFT]: LIFT (m/s, default 0.5) raises collider 0 at that
// speed; 0 holds it where it starts.
#include <nsf/runtime.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: %s MODEL SCENE MU [LIFT]\n", argv[0]);
    return 2;
  }
  try {
    nsf::RuntimeOptions options;
    options.mu = std::stod(argv[3]);
    options.threads = 2;
    nsf::Runtime rom(argv[1], argv[2], options);
    const double lift = argc > 4 ? std::stod(argv[4]) : 0.5;

    const std::vector<float> start = rom.positions();  // allocated by nsf, freed by the host
    std::vector<float> x(3 * rom.particle_count());    // the host's own buffer
    nsf::ColliderPose pose = rom.collider_pose(0);
    const double y0 = pose.position[1];
    std::printf("%zu particles, the first at %.4f %.4f %.4f; collider 0: %s at y = %.4f\n",
                rom.particle_count(), start[0], start[1], start[2], rom.collider_type(0).c_str(),
                y0);

    for (int frame = 1; frame <= rom.frame_count(); ++frame) {
      // The host's collider: raised at `lift` m/s, its pose and velocity set every frame.
      pose.position[1] = y0 + lift * rom.time();
      pose.velocity = {0.0, lift, 0.0};
      rom.set_collider_pose(0, pose);
      rom.advance_frame();

      rom.positions(x.data(), x.size());
      float lowest = x[1], mean_y = 0;
      for (std::size_t p = 0; p < rom.particle_count(); ++p) {
        lowest = std::min(lowest, x[3 * p + 1]);
        mean_y += x[3 * p + 1] / rom.particle_count();
      }
      std::printf(
          "frame %2d  t %.4f  collider y %.4f  mean y %.5f  lowest y %.5f  x0 %.5f %.5f %.5f\n",
          frame, rom.time(), rom.collider_pose(0).position[1], mean_y, lowest, x[0], x[1], x[2]);
    }
    // The bar as a rigid body, e.g. to attach a camera to it: its centre of mass, how far it
    // turned, and how far its particles are from a rigid copy of its rest shape.
    const nsf::ObjectPose bar = rom.object_pose(0);
    std::printf("object 0  centre %.5f %.5f %.5f  turned %.4f rad  misfit %.5f m\n",
                bar.position[0], bar.position[1], bar.position[2],
                std::acos(std::clamp((bar.rotation[0] + bar.rotation[4] + bar.rotation[8] - 1) / 2,
                                     -1.0, 1.0)),
                bar.misfit);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "embed: %s\n", e.what());
    return 1;
  }
  return 0;
}
