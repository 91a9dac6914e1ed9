#pragma once
// The steps `nsf demo` and `nsf report` chain: make a dataset unless it is complete, train a
// model unless a usable one exists. Each step is resumable on its own (sweep, train --resume).
#include <array>
#include <string>

namespace nsf::app {

// nsf sweep <scene> --out <data>: runs what is missing; returns the seconds spent.
double ensure_dataset(const std::string& scene, const std::string& data, int threads);

// nsf train <data> --out <model> with Table 1's networks for the scene and `steps` per stage,
// unless <model> exists and fits the dataset's scene (then it is reused). Returns true if it
// trained.
bool ensure_model(const std::string& data, const std::string& model,
                  const std::array<long, 3>& steps, int threads);

}  // namespace nsf::app
