#include "nn/dataset.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numeric>
#include <regex>

#include "core/error.h"
#include "core/input_file.h"
#include "core/strings.h"
#include "mpm/scene/settings_json.h"
#include "nn/dataset_gaps.h"

namespace nsf {

namespace fs = std::filesystem;

namespace {

// "train_12.h5" sorts after "train_2.h5": order runs by their number, not lexically.
std::vector<std::string> glob_runs(const fs::path& dir, const std::string& split) {
  const std::regex re(split + "_([0-9]+)\\.h5");
  std::vector<std::pair<long, std::string>> found;
  for (const auto& e : fs::directory_iterator(dir)) {
    std::smatch m;
    const std::string name = e.path().filename().string();
    if (std::regex_match(name, m, re)) found.emplace_back(std::stol(m[1]), name);
  }
  std::sort(found.begin(), found.end());
  std::vector<std::string> names;
  for (auto& f : found) names.push_back(f.second);
  return names;
}

// A run the manifest lists lives in the dataset's directory: a relative path with no ".." part.
// An absolute path or one that climbs out ("../x.h5", "/etc/passwd") is refused, so a manifest
// from elsewhere cannot make nsf open files outside the dataset.
std::string confined(const std::string& name, const std::string& manifest) {
  const fs::path p(name);
  bool climbs = false;
  for (const fs::path& part : p) climbs = climbs || part == "..";
  if (name.empty() || p.is_absolute() || p.has_root_name() || climbs ||
      name.find('\0') != std::string::npos)
    fail(manifest, ": run file \"", name,
         "\" is outside the dataset directory (a manifest lists files by names relative to its "
         "own directory, without \"..\")");
  return name;
}

std::string entry_file(const nlohmann::json& e, const std::string& manifest) {
  if (e.is_string()) return confined(e.get<std::string>(), manifest);
  if (e.is_object()) {
    for (const char* key : {"file", "path"})
      if (e.contains(key) && e[key].is_string())
        return confined(e[key].get<std::string>(), manifest);
  }
  fail(manifest, ": a run entry must be a file name or an object with \"file\", got ", e.dump());
}

void read_manifest(const fs::path& path, std::vector<std::string>& train,
                   std::vector<std::string>& test, PlannedRuns& planned) {
  const std::string text = read_input_file(path.string(), "dataset manifest");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    fail(path.string(), ": not valid JSON (", e.what(), ")");
  }
  planned = planned_in_manifest(j);
  for (auto [key, out] : {std::pair{"train", &train}, std::pair{"test", &test}})
    if (j.contains(key) && j[key].is_array())
      for (const auto& e : j[key]) out->push_back(entry_file(e, path.string()));
  for (const char* key : {"runs", "simulations"}) {
    if (!j.contains(key) || !j[key].is_array()) continue;
    for (const auto& e : j[key]) {
      const std::string split = e.is_object() ? e.value("split", "") : "";
      if (split == "train")
        train.push_back(entry_file(e, path.string()));
      else if (split == "test")
        test.push_back(entry_file(e, path.string()));
      else
        fail(path.string(), ": run entry without \"split\": \"train\"|\"test\": ", e.dump());
    }
  }
}

void to_float(const std::vector<Vec3>& v, std::vector<float>& out) {
  out.resize(3 * v.size());
  for (size_t p = 0; p < v.size(); ++p)
    for (int i = 0; i < 3; ++i) out[3 * p + i] = static_cast<float>(v[p][i]);
}

// The grid's corner, from the scene the run stored; runs without one used the default origin.
Vec3 run_domain_lo(const RunReader& r) {
  if (r.scene_json().empty()) return Vec3::Zero();
  const nlohmann::json j = nlohmann::json::parse(r.scene_json(), nullptr, false);
  if (j.is_discarded() || !j.contains("simulation")) return Vec3::Zero();
  return parse_settings(j["simulation"]).domain_lo;
}

// The frames a sweep's run holds when complete: its scene's simulation.frames + 1; 0 when unknown
// (a run not made by `nsf sweep`).
size_t planned_frames(const RunReader& r) {
  if (!r.has_attribute("sweep_parameter")) return 0;
  const nlohmann::json j = nlohmann::json::parse(r.scene_json(), nullptr, false);
  if (!j.is_object() || !j.contains("simulation") || !j["simulation"].is_object()) return 0;
  const nlohmann::json& f = j["simulation"].value("frames", nlohmann::json());
  return f.is_number_integer() && f.get<long>() > 0 ? size_t(f.get<long>()) + 1 : 0;
}

// A run's part of the training box, from the attributes `nsf sweep` writes (none in older files).
TrainingBox run_box(const RunReader& r, const SimulationFile& s) {
  nlohmann::json j = {{"parameters", nlohmann::json::array()},
                      {"colliders", nlohmann::json::array()}};
  const auto parsed = [&](const char* name) {
    const nlohmann::json v = nlohmann::json::parse(r.attribute_string(name), nullptr, false);
    if (v.is_discarded()) fail(s.path, ": attribute '", name, "' is not valid JSON");
    return v;
  };
  if (r.has_attribute("sweep_values")) {
    const nlohmann::json v = parsed("sweep_values");
    if (!v.is_object()) fail(s.path, ": attribute 'sweep_values' must be a JSON object");
    for (const auto& [name, value] : v.items()) {
      if (!value.is_number())
        fail(s.path, ": attribute 'sweep_values' holds '", name, "' = ", value.dump(),
             ", not a number");
      j["parameters"].push_back({{"name", name}, {"range", {value, value}}});
    }
  } else if (s.has_mu && r.has_attribute("sweep_parameter")) {
    j["parameters"].push_back(
        {{"name", r.attribute_string("sweep_parameter")}, {"range", {s.mu, s.mu}}});
  }
  if (r.has_attribute("collider_envelope")) j["colliders"] = parsed("collider_envelope");
  TrainingBox box = TrainingBox::from_json(j, s.path + ": the training box its attributes give");
  if (!r.scene_json().empty()) {
    const nlohmann::json scene = nlohmann::json::parse(r.scene_json(), nullptr, false);
    if (scene.is_discarded()) fail(s.path, ": attribute 'scene_json' is not valid JSON");
    box.scene = SceneFamily::of(scene);
  }
  return box;
}

}  // namespace

Dataset::Dataset(const std::string& dir, bool allow_incomplete) : dir_(dir) {
  const fs::path root(dir);
  if (!fs::is_directory(root))
    fail("dataset directory ", dir, fs::exists(root) ? " is not a directory" : " does not exist");
  std::vector<std::string> train, test;
  PlannedRuns planned;
  const fs::path manifest = root / "manifest.json";
  const bool has_manifest = fs::exists(manifest);
  if (has_manifest) read_manifest(manifest, train, test, planned);
  if (train.empty() && test.empty()) {
    train = glob_runs(root, "train");
    test = glob_runs(root, "test");
  }
  // What an interrupted or partial sweep left out (nn/dataset_gaps.h): listed runs without a
  // file, runs the plan has and the list lacks, runs killed mid-write, runs short of frames.
  std::vector<std::string> missing, unfinished = interrupted_runs(root);
  const auto path_of = [&](const std::string& name) { return root / name; };
  for (std::vector<std::string>* names : {&train, &test})
    names->erase(std::remove_if(names->begin(), names->end(),
                                [&](const std::string& n) {
                                  if (fs::exists(path_of(n))) return false;
                                  missing.push_back(n);
                                  return true;
                                }),
                 names->end());
  if (!has_manifest && !train.empty()) {  // a sweep killed before it wrote its manifest
    const RunReader first(path_of(train.front()).string());
    if (first.has_attribute("sweep_parameter")) planned = planned_in_scene(first.scene_json());
  }
  std::vector<std::string> listed = train;
  listed.insert(listed.end(), test.begin(), test.end());
  for (const std::string& n : unlisted_runs(planned, listed))
    if (std::find(missing.begin(), missing.end(), n) == missing.end()) missing.push_back(n);

  std::vector<Vec3> X0;
  std::string first;
  auto open = [&](const std::string& name, std::vector<SimulationFile>& out) {
    const fs::path p = path_of(name);
    auto r = std::make_unique<RunReader>(p.string());
    SimulationFile s;
    s.path = p.string();
    s.frames = r->frame_count();
    const size_t want = planned_frames(*r);
    if (want > 0 && s.frames < want) {
      unfinished.push_back(name + " (" + std::to_string(s.frames) + " of " + std::to_string(want) +
                           " frames)");
      return;
    }
    s.has_mu = r->has_attribute("mu");
    if (s.has_mu) s.mu = r->attribute_double("mu");
    s.box = run_box(*r, s);
    if (readers_.empty()) {
      first = s.path;
      X_ = r->rest_positions();
      scene_name_ = r->scene_name();
      has_mu_ = s.has_mu;
      volume_ = r->volume();
      object_ = r->object();
      dx_ = r->dx();
      domain_lo_ = run_domain_lo(*r);
    } else {
      if (r->rest_positions() != X_)
        fail("dataset ", dir, ": ", s.path, " is not the same scene as ", first,
             " (particle count or rest positions differ)");
      if (s.has_mu != has_mu_)
        fail("dataset ", dir, ": ", s.path, (s.has_mu ? " has" : " has no"), " attribute 'mu' but ",
             first, (has_mu_ ? " has" : " has not"));
    }
    if (s.frames == 0) fail("run ", s.path, " has no frames");
    readers_.push_back(std::move(r));
    out.push_back(s);
  };
  for (const auto& n : train) open(n, train_);
  for (const auto& n : test) open(n, test_);

  if (!missing.empty() || !unfinished.empty()) {
    std::string what;
    if (!missing.empty()) what += "\n  missing: " + join(missing);
    if (!unfinished.empty()) what += "\n  unfinished: " + join(unfinished);
    incomplete_ = "dataset " + dir + " is incomplete (an interrupted or partial sweep?):" + what;
    if (!allow_incomplete)
      fail(incomplete_, "\nfinish it with `nsf sweep SCENE --out ", dir,
           "` (it resumes where it stopped), or give --allow-incomplete to use the ", train_.size(),
           " training and ", test_.size(), " test runs it has");
  }
  if (train_.empty())
    fail("dataset ", dir,
         " has no training runs (expected manifest.json or train_<k>.h5 files; "
         "make one with `nsf sweep`)");
}

Dataset::~Dataset() = default;
Dataset::Dataset(Dataset&&) noexcept = default;
Dataset& Dataset::operator=(Dataset&&) noexcept = default;

TrainingBox training_box(const Dataset& data) {
  TrainingBox box;
  for (const SimulationFile& r : data.train()) box.include(r.box);
  return box;
}

const std::string& Dataset::scene_json() const {
  return readers_.front()->scene_json();
}

const RunReader& Dataset::reader(const SimulationFile& sim) const {
  for (const auto& r : readers_)
    if (r->path() == sim.path) return *r;
  fail("run ", sim.path, " is not part of dataset ", dir_);
}

FrameData Dataset::read_frame(const SimulationFile& sim, size_t k) const {
  const RunFrame f = reader(sim).read_frame(k);
  FrameData d;
  to_float(f.x, d.x);
  const size_t n = f.x.size();
  d.tau.resize(6 * n);
  d.C.resize(9 * n);
  for (size_t p = 0; p < n; ++p) {
    const Mat3& t = f.tau[p];
    const float s[6] = {float(t(0, 0)), float(t(1, 1)), float(t(2, 2)),
                        float(t(0, 1)), float(t(1, 2)), float(t(0, 2))};
    std::copy(s, s + 6, &d.tau[6 * p]);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) d.C[9 * p + 3 * i + j] = static_cast<float>(f.C[p](i, j));
  }
  return d;
}

std::vector<Vec3> Dataset::read_positions(const SimulationFile& sim, size_t k) const {
  return reader(sim).read_positions(k);
}

std::vector<float> Dataset::read_field(const SimulationFile& sim, size_t k,
                                       const std::string& field) const {
  // Stored as FrameData holds them: x y z, τ in run_format::kSymOrder, C row-major.
  const std::vector<double> v = reader(sim).read_frame_field(k, field);
  return std::vector<float>(v.begin(), v.end());
}

FrameStore::FrameStore(const Dataset& data, double budget_gib, int share, int shares,
                       bool positions_only)
    : data_(data),
      share_(share),
      shares_(shares),
      positions_only_(positions_only),
      budget_gib_(budget_gib) {
  if (shares < 1 || share < 0 || share >= shares)
    fail("frame store: share ", share, " of ", shares, " does not exist");
  for (size_t s = 0; s < data.train().size(); ++s) {
    run_start_.push_back(index_.size());
    for (size_t k = 0; k < data.train()[s].frames; ++k) index_.emplace_back(s, k);
  }
  const size_t held = (index_.size() + size_t(shares - share - 1)) / size_t(shares);
  const double gib = double(held) * double(data.particle_count()) * (positions_only ? 3 : 18) *
                     sizeof(float) / (1024.0 * 1024.0 * 1024.0);
  cached_ = gib <= budget_gib;
  if (cached_) {
    cached_gib_ = gib;
    frames_.reserve(held);
    for (size_t i = size_t(share); i < index_.size(); i += size_t(shares))
      frames_.push_back(read(i));
  }
}

FrameData FrameStore::read(size_t i) const {
  const SimulationFile& run = data_.train()[index_[i].first];
  if (!positions_only_) return data_.read_frame(run, index_[i].second);
  FrameData d;
  d.x = data_.read_field(run, index_[i].second, "x");
  return d;
}

size_t FrameStore::index_of(size_t sim, size_t k) const {
  if (sim >= run_start_.size() || k >= data_.train()[sim].frames) return kNone;
  return run_start_[sim] + k;
}

const FrameData& FrameStore::get(size_t i) const {
  if (cached_ && holds(i)) return frames_[i / size_t(shares_)];
  if (scratch_index_ != i) scratch_ = read(i), scratch_index_ = i;
  return scratch_;
}

}  // namespace nsf
