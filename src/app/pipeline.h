#pragma once
// The steps `nsf demo` and `nsf report` chain: make a dataset unless it is complete, train a
// model unless a usable one exists. Each step is resumable on its own (sweep, train --resume).
#include <array>
#include <string>

namespace nsf::app {

// nsf sweep <scene> --out <data>: runs what is missing; returns the seconds spent.
double ensure_dataset(const std::string& scene, const std::string& data, int threads);

// What ensure_model trains: steps per stage and, where > 0, decoder widths (g, h, l) in place
// of Table 1's for the scene.
struct TrainPlan {
  std::array<long, 3> steps = {2000, 1500, 1500};
  std::array<int, 3> widths = {0, 0, 0};
};

// nsf train <data> --out <model> by `plan`, unless <model> exists and fits the dataset's scene
// (then it is reused). Returns true if it trained.
bool ensure_model(const std::string& data, const std::string& model, const TrainPlan& plan,
                  int threads);

}  // namespace nsf::app
