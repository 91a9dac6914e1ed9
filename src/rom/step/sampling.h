#pragma once
// Sample particles S (§5.4): which particles the Gauss–Newton inversion fits. Random (seeded),
// clustered around a point of the rest shape (the cake clusters them toward the cut), and a
// schedule that shrinks S over time (the cake goes from 700 to 400 after T/2). A scene may carry
// these choices in an optional "rom" section (docs/ROM.md); the command line overrides them.
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/types.h"

namespace nsf {

struct SampleChange {
  double fraction = 0.5;  // of the run's duration T
  int count = 0;          // |S| from then on (at most the initial count)
};

struct SamplingSpec {
  int count = 256;  // |S| at t = 0
  // "random", "cluster", or "qdeim": the particles QDEIM picks on g's tangent directions
  // first (rom/step/sample_selection.h; the latent stepper ranks them), then random ones.
  std::string mode = "random";
  Vec3 center = Vec3::Zero();  // cluster: centre in rest space (m) ...
  double sigma = 0;            // ... and Gaussian width (m) of the sampling weight
  uint64_t seed = 1;
  std::vector<SampleChange> schedule;  // sorted by fraction
};

// The keys of a scene's "rom" section that parse_sampling reads.
const std::vector<std::string>& sampling_keys();

// Reads the sampling's keys of a scene's "rom" section (missing keys keep the defaults above).
// Throws nsf::Error naming the key for a malformed value, or for a key it does not read (the
// caller, rom/setup/rom_section.h, hands it the section without the keys it reads itself).
SamplingSpec parse_sampling(const nlohmann::json& rom_section);

// The particles in the order they join S: S at any time is the first sample_count_at(t) entries,
// so a schedule that shrinks S keeps a subset of the particles the latents were fitted to.
// Throws nsf::Error if the spec asks for more particles than X holds or fewer than one.
std::vector<uint32_t> rank_samples(const std::vector<Vec3>& X, const SamplingSpec& spec);

// |S| at time t of a run of duration T; never above spec.count (S only shrinks).
int sample_count_at(const SamplingSpec& spec, double t, double T);

}  // namespace nsf
