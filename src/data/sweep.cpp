#include "data/sweep.h"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <mutex>
#include <thread>

#include "core/error.h"
#include "core/progress.h"
#include "core/timer.h"
#include "data/manifest.h"
#include "data/run_to_file.h"
#include "io/run_reader.h"
#include "mpm/scene/settings_json.h"
#include "mpm/simulation.h"

namespace nsf {
namespace fs = std::filesystem;

namespace {

struct Job {
  int plan_index = 0;  // in plan_sweep's list
  SweepRun run;
  nlohmann::json scene;  // μ applied
  std::string path;
  int frames = 0;
  std::string scene_dir;  // relative mesh paths in the scene resolve against it
};

// Shared by the worker threads: the next job to take, the progress line, the first error.
struct Pool {
  std::atomic<size_t> next{0};
  std::atomic<bool> failed{false};
  RunWriterOptions writer;  // set before the workers start
  std::mutex mutex;         // guards everything below
  Progress* progress = nullptr;
  long frames_done = 0;
  int runs_done = 0;
  std::vector<int> done;  // plan indices of the runs completed
  std::string error;
};

void simulate_job(const Job& job, const SweepSpec& spec, Pool& pool, int total_runs) {
  Scene scene;
  try {
    scene = build_scene(job.scene, job.scene_dir);
  } catch (const Error& e) {
    fail(job.path, ": scene at mu = ", job.run.mu, ": ", e.what());
  }
  Simulation sim(std::move(scene));
  RunAttributes attributes;
  attributes.numbers["mu"] = job.run.mu;
  attributes.strings["split"] = job.run.split;
  attributes.strings["sweep_parameter"] = spec.parameter;
  attributes.strings["sweep_values"] = sweep_values(spec, job.run).dump();
  run_to_file(
      sim, job.path, attributes,
      [&](int) {
        std::lock_guard<std::mutex> lock(pool.mutex);
        ++pool.frames_done;
        if (pool.progress)
          pool.progress->update(pool.frames_done, "runs " + std::to_string(pool.runs_done) + "/" +
                                                      std::to_string(total_runs) + " done");
      },
      pool.writer);
  std::lock_guard<std::mutex> lock(pool.mutex);
  ++pool.runs_done;
  pool.done.push_back(job.plan_index);
}

void worker(const std::vector<Job>& jobs, const SweepSpec& spec, int threads, Pool& pool) {
  // OpenMP's thread count is per calling thread, so each job slot sets its own.
  omp_set_num_threads(threads);
  for (;;) {
    const size_t i = pool.next++;
    if (i >= jobs.size() || pool.failed) return;
    try {
      simulate_job(jobs[i], spec, pool, int(jobs.size()));
    } catch (const std::exception& e) {
      // Other slots finish their current run (it is valid data) but take no new one.
      std::lock_guard<std::mutex> lock(pool.mutex);
      if (!pool.failed.exchange(true)) pool.error = e.what();
    }
  }
}

// The jobs the team gives this process out of those pending here (another process may see
// the files differently, so they are looked up among all selected).
std::vector<Job> team_share(SweepTeam& team, const std::vector<Job>& pending,
                            const std::vector<Job>& selected) {
  std::vector<int> indices;
  for (const Job& job : pending) indices.push_back(job.plan_index);
  std::vector<Job> mine;
  for (int i : team.share(indices)) {
    auto it = std::find_if(selected.begin(), selected.end(),
                           [i](const Job& job) { return job.plan_index == i; });
    if (it == selected.end())
      fail("sweep: the team gave this process run ", i, ", not selected here");
    mine.push_back(*it);
  }
  return mine;
}

}  // namespace

namespace {
// The scene without the keys that do not change what is simulated, so that editing a
// description, a camera, the reduced-order samples or the training recipe does not redo a
// finished sweep.
nlohmann::json simulated_part(const std::string& scene_json) {
  nlohmann::json j = nlohmann::json::parse(scene_json, nullptr, false);
  if (j.is_object())
    for (const char* key : {"description", "camera", "rom", "train"}) j.erase(key);
  return j;
}
}  // namespace

bool is_complete_run(const std::string& path, const std::string& scene_json, int frames) {
  if (!fs::exists(path)) return false;
  try {
    RunReader r(path);
    return r.frame_count() == size_t(frames) + 1 &&
           simulated_part(r.scene_json()) == simulated_part(scene_json);
  } catch (const Error&) {
    return false;
  }
}

SweepSummary run_sweep(const std::string& scene_path, const SweepOptions& opt) {
  const nlohmann::json scene = read_scene_json(scene_path, opt.overrides);
  std::optional<SweepSpec> spec;
  try {
    if (scene.is_object() && scene.contains("sweep")) spec = parse_sweep(scene.at("sweep"), scene);
  } catch (const Error& e) {
    fail(scene_path, ": ", e.what());
  }
  return run_sweep(scene, spec, scene_path, opt);
}

SweepSummary run_sweep(const nlohmann::json& base, const std::optional<SweepSpec>& sweep,
                       const std::string& scene_path, const SweepOptions& opt) {
  if (!opt.only.empty() && opt.only != "train" && opt.only != "test")
    fail("sweep: --only must be 'train' or 'test', got '", opt.only, "'");
  if (opt.jobs < 1 || opt.threads < 1) fail("sweep: jobs and threads must be at least 1");
  if (!sweep) fail(scene_path, ": the scene has no 'sweep' section (docs/SCENES.md, \"Sweeps\")");
  const SweepSpec& spec = *sweep;
  const std::string scene_dir = fs::path(scene_path).parent_path().string();
  try {
    build_scene(base, scene_dir);  // validates what the engine reads once, with the file's own μ
  } catch (const Error& e) {
    fail(scene_path, ": ", e.what());
  }
  fs::create_directories(opt.out_dir);

  const std::vector<SweepRun> plan = plan_sweep(spec);
  SweepSummary summary;
  std::vector<Job> selected, pending;
  for (int i = 0; i < int(plan.size()); ++i) {
    const SweepRun& run = plan[i];
    if (!opt.only.empty() && run.split != opt.only) continue;
    ++summary.planned;
    Job job{i, run, base, (fs::path(opt.out_dir) / run.file()).string(), 0, scene_dir};
    try {
      apply_sweep_run(spec, run, job.scene);
      job.frames = parse_settings(job.scene.at("simulation"), "simulation").frames;
    } catch (const Error& e) {
      fail(scene_path, ": sweep run ", run.file(), " (mu = ", run.mu, "): ", e.what());
    }
    if (is_complete_run(job.path, job.scene.dump(), job.frames))
      ++summary.skipped;
    else
      pending.push_back(job);
    selected.push_back(std::move(job));
  }
  if (opt.team) pending = team_share(*opt.team, pending, selected);
  long pending_frames = 0;
  for (const Job& job : pending) pending_frames += job.frames;

  const double start = now_seconds();
  Pool pool;
  pool.writer.gzip_level = opt.gzip;
  Progress progress("sweep " + base.value("name", std::string("scene")), pending_frames, "frames");
  if (!opt.quiet) pool.progress = &progress;
  std::vector<std::thread> slots;
  const int jobs = std::min<int>(opt.jobs, std::max<int>(1, int(pending.size())));
  for (int j = 0; j < jobs; ++j)
    slots.emplace_back(worker, std::cref(pending), std::cref(spec), opt.threads, std::ref(pool));
  for (std::thread& t : slots) t.join();
  summary.ran = pool.runs_done;
  summary.seconds = now_seconds() - start;
  if (!opt.quiet && !pending.empty()) progress.finish();

  // The manifest lists every complete run of the whole sweep, also those of an earlier
  // `--only` pass, so train and test may be generated separately. With a team, also every run
  // another process reports complete: on a network file system this process may not see
  // another host's new files yet.
  const auto write_manifest = [&](const std::vector<int>& done) {
    std::vector<bool> listed(plan.size(), false);
    for (int i : done) listed.at(i) = true;
    std::vector<SweepRun> complete;
    for (int i = 0; i < int(plan.size()); ++i) {
      const SweepRun& run = plan[i];
      nlohmann::json j = base;
      apply_sweep_run(spec, run, j);
      const int frames = parse_settings(j.at("simulation"), "simulation").frames;
      if (listed[i] ||
          is_complete_run((fs::path(opt.out_dir) / run.file()).string(), j.dump(), frames))
        complete.push_back(run);
    }
    write_json_atomically((fs::path(opt.out_dir) / "manifest.json").string(),
                          make_manifest(base.value("name", std::string()), scene_path, spec,
                                        opt.overrides, complete));
    summary.ran = int(done.size());
  };
  if (opt.team) {
    opt.team->collect(pool.done, write_manifest);
    summary.seconds = now_seconds() - start;  // until the last process finished
  } else {
    write_manifest(pool.done);
  }
  if (pool.failed) fail("sweep stopped: ", pool.error);
  return summary;
}

}  // namespace nsf
