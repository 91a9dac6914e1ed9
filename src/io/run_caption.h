#pragma once
// Captions that tell runs apart on a picture with one row per run (`nsf contact-sheet`, the
// ground truth | ROM comparison): the scene, where the run came from (a simulation or the
// reduced-order model), the sweep parameter μ and the file, read from the run's attributes.
#include <optional>
#include <string>
#include <vector>

#include "io/image.h"
#include "io/run_reader.h"

namespace nsf {

struct RunFacts {
  std::string file;       // the path as given
  std::string scene;      // scene_name
  bool rom = false;       // written by `nsf rom` (attribute "rom")
  std::string split;      // "train" or "test" for a sweep's runs (attribute "split")
  std::string parameter;  // what μ is, e.g. "hardening" (attribute "sweep_parameter")
  std::optional<double> mu;
};

RunFacts run_facts(const RunReader& run);

// "metal_small · μ = 0.05 (hardening)": the scene and the parameter, without source or file.
std::string run_description(const RunFacts& run);

// One caption per row: "metal_small · μ = 0.05 (hardening) · simulation, test run · test_0.h5".
// The file is named by its file name, or by its path where two rows share a file name, so no two
// rows showing different files read the same.
std::vector<std::string> row_captions(const std::vector<RunFacts>& runs);

// `row` under a white band that holds `caption` in text of `size` (text.h).
Image captioned(const Image& row, const std::string& caption, double size);

}  // namespace nsf
