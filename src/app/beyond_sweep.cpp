#include "app/beyond_sweep.h"

#include <map>

namespace nsf::app {

std::vector<BeyondSweepCase> beyond_sweep_cases(const std::string& base) {
  // Each changes what the scene's sweep holds fixed; the sizes and scenes' layouts are in
  // scenes/paper/*_small.json and *_paper.json alike.
  static const std::map<std::string, std::vector<BeyondSweepCase>> cases = {
      // The plates squeeze 20 % deeper (to 0.36 / 0.64 instead of 0.35 / 0.65).
      {"metal",
       {{"plates squeeze deeper",
         {"colliders[1].motion.keyframes[1].center=[0.36,0.3,0.5]",
          "colliders[2].motion.keyframes[1].center=[0.64,0.3,0.5]"}}}},
      // The grips pull apart a quarter faster.
      {"bread",
       {{"grips pull 1.25x faster",
         {"colliders[0].motion.velocity=[-0.125,0,0]",
          "colliders[1].motion.velocity=[0.125,0,0]"}}}},
      // The blade stops halfway down instead of cutting through.
      {"cake", {{"blade stops halfway", {"colliders[1].motion.end=0.25"}}}},
      // The paste is laid three times as fast along the brush.
      {"toothpaste", {{"paste laid 3x faster along", {"objects[0].velocity=[0.15,-0.4,0]"}}}},
      // Friction past the trained range (20-40°), App. B.
      {"sand", {{"friction angle 44°", {}, 44, false}}},
  };
  const auto it = cases.find(base);
  return it == cases.end() ? std::vector<BeyondSweepCase>{} : it->second;
}

}  // namespace nsf::app
