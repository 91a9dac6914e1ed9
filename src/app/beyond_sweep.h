#pragma once
// Held-out cases outside a scene's sweep family (issue #25 point 5): the same scene at its first
// test μ with something the sweep never varies changed, so that the training runs have nothing
// to play back. `nsf report --beyond-sweep` runs them; their rows are labelled "beyond-sweep: …".
#include <string>
#include <vector>

namespace nsf::app {

struct BeyondSweepCase {
  std::string what;              // the label's text after "beyond-sweep: "
  std::vector<std::string> set;  // --set overrides, applied before μ
  double mu = 0;                 // the μ to run at
  bool at_test_mu = true;        // true: the dataset's first test μ, not `mu`
};

// The cases of one of the paper's scenes ("metal", "sand", …); none for a scene without any.
std::vector<BeyondSweepCase> beyond_sweep_cases(const std::string& base_scene);

}  // namespace nsf::app
