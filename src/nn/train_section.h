#pragma once
// The optional "train" section of a scene (its "calibrate" aside, which is the ROM's:
// rom/calibration/calibration_recipe.h): the training recipe that `nsf train`, `nsf report` and
// `nsf demo` use for it where their command lines do not give one (docs/SCENES.md, "Training
// recipe").
// A scene whose fields need more than the commands' common recipe carries its own here: the
// jelly's encoder, for one (docs/TRAINING.md).
#include <array>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace nsf {

struct TrainSection {
  std::optional<std::array<long, 3>> steps;  // optimiser steps of stages 1, 2, 3
  std::optional<std::array<int, 3>> widths;  // hidden widths of g, h, l
  int encoder_max_length = 0;                // 0: App. E's (the encoder's default)
  int latent_dim = 0;                        // r; 0: Table 1's for the scene
  std::string decoder;                       // "mlp" or "basis"; "": the commands' default
  std::string encoder;                       // "network" or "modes" (basis); "": the default
  // A stage's batch: frames, then particles within each frame.
  std::optional<std::array<int, 3>> frames_per_batch, particles_per_frame;
};

TrainSection parse_train_section(const nlohmann::json& train, const std::string& path = "train");

// A training recipe as `nsf train`, `nsf report` and `nsf demo` settle it from their command
// lines and the scene's section: steps per stage and, where > 0, decoder widths (g, h, l) in
// place of Table 1's for the scene.
struct TrainPlan {
  std::array<long, 3> steps = {2000, 1500, 1500};
  std::array<int, 3> widths = {0, 0, 0};
  int encoder_max_length = 0;                          // 0: App. E's
  int latent_dim = 0;                                  // 0: Table 1's for the scene
  std::array<int, 3> frames_per_batch = {0, 0, 0};     // per stage; 0: the trainer's default
  std::array<int, 3> particles_per_frame = {0, 0, 0};  // likewise
  std::string decoder;       // the decoder family, "mlp" or "basis"; "": NetConfig's default
  std::string encoder;       // a basis model's encoder, "network" or "modes"; "": NetConfig's
  bool steps_given = false;  // a command line gave the steps (else a family may set its own)
};

// Which of a recipe's values a command line gave itself: those keep the command line's.
struct GivenOnCommandLine {
  bool steps = false;
  std::array<bool, 3> widths = {false, false, false};  // g, h, l
  bool encoder_max_length = false, frames_per_batch = false, particles_per_frame = false;
  bool latent_dim = false;
  bool decoder = false;
  bool encoder = false;
};

// `plan` with the section's values in place of those the command line did not give.
TrainPlan with_train_section(TrainPlan plan, const TrainSection& section,
                             const GivenOnCommandLine& given);

// What with_train_section takes from `section`, for the log: "steps 34000,1500,1500; width g
// 192; encoder_max_length 1024; r 8" ("" if nothing).
std::string recipe_taken(const TrainSection& section, const GivenOnCommandLine& given);

}  // namespace nsf
