#include "rom/step/sampling.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include "core/error.h"
#include "core/strings.h"

namespace nsf {

const std::vector<std::string>& sampling_keys() {
  static const std::vector<std::string> keys = {"samples", "sampling", "center",
                                                "sigma",   "seed",     "schedule"};
  return keys;
}

SamplingSpec parse_sampling(const nlohmann::json& rom) {
  SamplingSpec s;
  if (rom.is_null()) return s;
  if (!rom.is_object()) fail("scene key 'rom' must be an object, got ", rom.dump());
  for (const auto& [key, value] : rom.items()) {
    const std::string path = "rom." + key;
    if (key == "samples") {
      if (!value.is_number_integer() || value.get<long>() < 1)
        fail("scene key '", path, "' must be a positive integer, got ", value.dump());
      s.count = value.get<int>();
    } else if (key == "sampling") {
      if (!value.is_string() || (value != "random" && value != "cluster" && value != "qdeim"))
        fail("scene key '", path, "' must be \"random\", \"cluster\" or \"qdeim\", got ",
             value.dump());
      s.mode = value.get<std::string>();
    } else if (key == "center") {
      if (!value.is_array() || value.size() != 3 || !value[0].is_number() ||
          !value[1].is_number() || !value[2].is_number())
        fail("scene key '", path, "' must be [x, y, z], got ", value.dump());
      s.center = Vec3(value[0].get<double>(), value[1].get<double>(), value[2].get<double>());
    } else if (key == "sigma") {
      if (!value.is_number() || value.get<double>() <= 0)
        fail("scene key '", path, "' must be a positive length in metres, got ", value.dump());
      s.sigma = value.get<double>();
    } else if (key == "seed") {
      if (!value.is_number_integer() || value.get<long>() < 0)
        fail("scene key '", path, "' must be a non-negative integer, got ", value.dump());
      s.seed = value.get<uint64_t>();
    } else if (key == "schedule") {
      if (!value.is_array())
        fail("scene key '", path, "' must be a list of {\"fraction\", \"samples\"}, got ",
             value.dump());
      for (size_t i = 0; i < value.size(); ++i) {
        const auto& e = value[i];
        const std::string ep = path + "[" + std::to_string(i) + "]";
        if (!e.is_object() || !e.contains("fraction") || !e.contains("samples") ||
            !e["fraction"].is_number() || !e["samples"].is_number_integer())
          fail("scene key '", ep, "' must be {\"fraction\": f, \"samples\": k}, got ", e.dump());
        SampleChange c{e["fraction"].get<double>(), e["samples"].get<int>()};
        if (!(c.fraction > 0 && c.fraction < 1))
          fail("scene key '", ep, ".fraction' must lie in (0, 1), got ", c.fraction);
        if (c.count < 1) fail("scene key '", ep, ".samples' must be positive, got ", c.count);
        s.schedule.push_back(c);
      }
      std::sort(s.schedule.begin(), s.schedule.end(),
                [](const auto& a, const auto& b) { return a.fraction < b.fraction; });
    } else {
      fail("scene key '", path, "' is not a sampling key (", join(sampling_keys()), ")");
    }
  }
  if (s.mode == "cluster" && s.sigma <= 0)
    fail("scene key 'rom.sampling' is \"cluster\" but 'rom.sigma' (the cluster width) is missing");
  for (const auto& c : s.schedule)
    if (c.count > s.count)
      fail("scene key 'rom.schedule': a change to ", c.count,
           " samples exceeds the initial 'rom.samples' = ", s.count, " (S may only shrink)");
  return s;
}

std::vector<uint32_t> rank_samples(const std::vector<Vec3>& X, const SamplingSpec& spec) {
  const size_t n = X.size();
  if (spec.count < 1) fail("sample particles: |S| must be at least 1, got ", spec.count);
  if (size_t(spec.count) > n)
    fail("sample particles: |S| = ", spec.count, " exceeds the scene's ", n, " particles");
  std::mt19937_64 rng(spec.seed);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  // Weighted sampling without replacement (Efraimidis–Spirakis): the k largest keys
  // log(u)/w are a sample with probabilities proportional to w; uniform w is plain random.
  std::vector<double> key(n);
  for (size_t p = 0; p < n; ++p) {
    double w = 1.0;
    if (spec.mode == "cluster")
      w = std::exp(-(X[p] - spec.center).squaredNorm() / (2 * spec.sigma * spec.sigma)) + 1e-300;
    key[p] = std::log(std::max(uni(rng), 1e-300)) / w;
  }
  std::vector<uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  std::partial_sort(
      order.begin(), order.begin() + spec.count, order.end(),
      [&](uint32_t a, uint32_t b) { return key[a] > key[b] || (key[a] == key[b] && a < b); });
  order.resize(spec.count);
  return order;
}

int sample_count_at(const SamplingSpec& spec, double t, double T) {
  int count = spec.count;
  // S only shrinks: a later size above the initial one (a --samples below the scene's schedule,
  // which the scene's own check never saw) keeps the initial.
  for (const auto& c : spec.schedule)
    if (t >= c.fraction * T) count = std::min(c.count, spec.count);
  return count;
}

}  // namespace nsf
