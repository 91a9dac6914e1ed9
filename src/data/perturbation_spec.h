#pragma once
// The optional "generalize" section of a scene (docs/GENERALIZE.md): interactions outside the
// scene's sweep, from which `nsf generalize` draws the unseen cases it scores a reduced model on.
// Each perturbation changes something the sweep holds fixed (a collider's speed, path or stopping
// point, a throw's direction, the ground's slope, where an object starts) through override
// templates in one value v, like the sweep's templates in μ:
//   {"name": "plates squeeze deeper", "range": [0.355, 0.38],
//    "set": ["colliders[1].motion.keyframes[1].center=[{v},0.3,0.5]", ...]}
// A draw takes one perturbation (in turn), v uniform in its range, μ and the sweep's other axes
// uniform in theirs, from a seeded generator: the same seed gives the same draws on every machine.
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "data/parameter_axis.h"
#include "data/sweep_spec.h"

namespace nsf {

using Perturbation = ParameterAxis;

struct GeneralizeSpec {
  std::vector<Perturbation> perturbations;
  int draws = 10;     // how many cases `nsf generalize` scores by default
  uint64_t seed = 1;  // of the draws
  // Of the draws `nsf calibrate --unseen` measures a model's unseen profile on: other cases of
  // the same perturbations, never the benchmark's (default: seed + 1000; never seed itself).
  uint64_t calibration_seed = 1001;
};

struct PerturbationDraw {
  int index = 0;
  std::string perturbation;            // its name
  double value = 0;                    // v
  double mu = 0;                       // μ (0 where the scene has no sweep)
  std::vector<double> values;          // the sweep's "vary" axes, each uniform in its range
  std::vector<std::string> overrides;  // the perturbation's templates at v (μ not included)
};

// Reads and validates the section. `scene` is the whole scene and `sweep` its sweep (none: the
// scene has none): every template is applied at both ends of its range, and must change the scene
// there, also after the sweep's templates (applied after it in a run) at either end of μ's range:
// a perturbation that leaves the scene as the sweep makes it would score the training family, not
// an unseen case.
GeneralizeSpec parse_generalize(const nlohmann::json& section, const nlohmann::json& scene,
                                const SweepSpec* sweep);

// `count` draws from `seed`; μ and the "vary" axes uniform in their ranges where `sweep` is given.
std::vector<PerturbationDraw> plan_draws(const GeneralizeSpec& spec, const SweepSpec* sweep,
                                         int count, uint64_t seed);

}  // namespace nsf
