#include "nn/config.h"

#include "core/error.h"

#include <algorithm>
#include <cctype>

namespace nsf {

const char* family_name(DecoderFamily family) {
  return family == DecoderFamily::mlp ? "mlp" : "basis";
}

DecoderFamily parse_family(const std::string& name, const std::string& what) {
  if (name == "basis") return DecoderFamily::basis;
  if (name == "mlp") return DecoderFamily::mlp;
  fail(what, ": unknown decoder family '", name, "' (known: basis, mlp)");
}

const char* const kStageNames[kStageCount] = {"deformation", "stress", "affine"};

namespace {

struct Row {
  const char* scene;
  int r, beta_g, beta_h, beta_l;
};

// Table 1: dim(L) and the MLP widths β·d for g (d = 3), h (d = 6) and l (d = 9).
constexpr Row kTable1[] = {
    {"bread", 6, 48, 64, 64},        {"cake", 6, 48, 64, 64},       {"sand", 6, 48, 72, 72},
    {"metal", 5, 32, 48, 48},        {"toothpaste", 6, 32, 48, 48}, {"jelly", 5, 32, 64, 64},
    {"squishy_ball", 6, 48, 64, 72},
};

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

}  // namespace

NetConfig default_net_config(const std::string& scene_name, std::string* matched) {
  // Match on a prefix so that variants ("sand_small", "jelly_cube") find their paper row.
  const std::string name = lower(scene_name);
  const Row* row = nullptr;
  for (const Row& r : kTable1)
    if (name.rfind(r.scene, 0) == 0) row = &r;
  NetConfig c;
  if (matched) *matched = row ? row->scene : "default";
  if (!row) row = &kTable1[0];
  c.latent_dim = row->r;
  c.width_g = row->beta_g * 3;
  c.width_h = row->beta_h * 6;
  c.width_l = row->beta_l * 9;
  return c;
}

double learning_rate(long step, long total_steps) {
  if (total_steps <= 0) return kLearningRates[0];
  const long n = static_cast<long>(kLearningRates.size());
  const long k = std::min(n - 1, step * n / total_steps);
  return kLearningRates[std::max(0L, k)];
}

void apply_family_defaults(TrainConfig& c, bool steps_given, bool noise_given) {
  if (c.net.decoder != DecoderFamily::basis) return;
  if (!steps_given) c.steps[1] = c.steps[2] = kBasisCoefficientSteps;
  if (!noise_given) c.latent_noise = kBasisLatentNoise;
}

}  // namespace nsf
