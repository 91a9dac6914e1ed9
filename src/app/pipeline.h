#pragma once
// The steps `nsf demo` and `nsf report` chain: make a dataset unless it is complete, train a
// model unless a usable one exists. Each step is resumable on its own (sweep, train --resume).
#include <string>

#include "nn/config.h"
#include "nn/train_section.h"

namespace nsf::app {

// The recipe `nsf demo` and `nsf report` train with unless told: stages of 6000, 4000, 4000 steps
// and, for the MLP fields, h and l 128 wide (smaller than Table 1, so that training takes minutes
// on 2 cores); a basis model's stages 2 and 3 take its own defaults (nn/config.h).
TrainPlan chain_plan();

// nsf sweep <scene> --out <data>: runs what is missing, `threads` runs at once (> 0); returns
// the seconds spent.
double ensure_dataset(const std::string& scene, const std::string& data, int threads,
                      bool quiet = false);

// `plan` with the scene file's own "train" section in place of the values the command line did
// not give.
TrainPlan with_scene_recipe(TrainPlan plan, const std::string& scene, bool steps_given,
                            bool widths_given);

// The decoder family a scene's models hold: its recipe's "decoder", else the trainer's default.
std::string scene_decoder(const std::string& scene);

// Where `nsf report --decoder FAMILY` keeps a scene's model and rows. A family other than the
// scene's own gets a model of its own, models/NAME_FAMILY.nsf, and rows of its own beside the
// scene's, their tags ending in _FAMILY and labelled with it; the scene's own family (or none
// asked) keeps models/NAME.nsf and the plain rows.
struct DecoderRows {
  std::string model;       // models/NAME[_FAMILY].nsf
  std::string tag_suffix;  // "" or "_mlp", "_basis"
  std::string label;       // "" or "MLP fields", "per-point bases"
};
DecoderRows decoder_rows(const std::string& name, const std::string& own, const std::string& asked);

// `plan`'s steps, and its widths, encoder length and batches where it sets them (> 0), into the
// trainer's configuration: what `nsf train` takes from a scene's recipe, and `ensure_model`.
void apply_plan(const TrainPlan& plan, TrainConfig& config);

// nsf train <data> --out <model> by `plan`, unless <model> exists and fits the dataset's scene
// (then it is reused). Returns true if it trained.
bool ensure_model(const std::string& data, const std::string& model, const TrainPlan& plan,
                  int threads, bool quiet = false);

}  // namespace nsf::app
