// load_scene and simulate: a scene file as the engine builds it (μ and overrides applied), and a
// full-order run of it written to a run file, as `nsf simulate` and `nsf sweep` write them.
#include <omp.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "bindings.h"
#include "core/error.h"
#include "data/run_to_file.h"
#include "data/sweep_spec.h"
#include "mpm/scene/scene.h"
#include "mpm/simulation.h"

namespace py = pybind11;

namespace nsf::python {

namespace {

static_assert(sizeof(Vec3) == 3 * sizeof(double), "a std::vector<Vec3> is a P×3 array");

// A scene file, loaded: the JSON the engine runs (overrides, then μ's sweep templates applied)
// and the scene built from it, for its settings and initial particles.
struct LoadedScene {
  std::string path;
  std::optional<double> mu;
  std::vector<std::string> overrides;
  nlohmann::json json;
  std::optional<SweepSpec> sweep;
  Scene scene;

  std::string dir() const { return std::filesystem::path(path).parent_path().string(); }
};

std::unique_ptr<LoadedScene> load(const std::string& path, std::optional<double> mu,
                                  const std::vector<std::string>& overrides) {
  check_input_path(path, "scene file");
  check_mu(mu);
  auto s = std::make_unique<LoadedScene>();
  s->path = path, s->mu = mu, s->overrides = overrides;
  s->json = read_scene_json(path, overrides);  // errors name the file
  try {
    if (s->json.contains("sweep")) {
      s->sweep = parse_sweep(s->json.at("sweep"), s->json);
      if (mu) apply_overrides(s->json, sweep_overrides(*s->sweep, *mu));
    } else if (mu) {
      fail("mu given, but the scene has no \"sweep\" section saying what mu is");
    }
    s->scene = build_scene(s->json, s->dir());
  } catch (const Error& e) {
    fail(path, ": ", e.what());
  }
  return s;
}

// Runs the scene from its initial state to its last frame, writing every frame to `out` (under a
// temporary name until complete). The GIL stays held: HDF5 is not thread-safe, and h5py shares
// the library. Ctrl-C stops it between frames, leaving no file.
void simulate(const LoadedScene& s, const std::string& out, long long threads) {
  check_threads(threads);  // before OpenMP sees it: 10**9 made libgomp abort the interpreter
  const int before = omp_get_max_threads();
  if (threads > 0) omp_set_num_threads(int(threads));
  try {
    Simulation sim(build_scene(s.json, s.dir()));
    RunAttributes attributes;
    if (s.mu) attributes.numbers["mu"] = *s.mu;
    run_to_file(sim, out, attributes, [](int) {
      if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    });
  } catch (...) {
    omp_set_num_threads(before);
    throw;
  }
  omp_set_num_threads(before);
}

py::object sweep_dict(const std::optional<SweepSpec>& sweep) {
  if (!sweep) return py::none();
  return py::dict(py::arg("parameter") = sweep->parameter, py::arg("lo") = sweep->lo,
                  py::arg("hi") = sweep->hi, py::arg("train") = sweep->train,
                  py::arg("test") = sweep->test);
}

}  // namespace

void bind_scene(py::module_& m) {
  py::class_<LoadedScene>(m, "Scene",
                          "A scene file (docs/SCENES.md) loaded as the engine builds it, with its "
                          "overrides and mu applied: what nsf.load_scene returns.")
      .def(py::init(&load), py::arg("path"), py::arg("mu") = py::none(),
           py::arg("overrides") = std::vector<std::string>(),
           "Loads the scene file `path` with `overrides` (\"a.b=value\") and then `mu` applied; "
           "nsf.load_scene is the checked way to call it.")
      .def_readonly("path", &LoadedScene::path, "the scene file")
      .def_readonly("mu", &LoadedScene::mu, "the sweep parameter applied, or None")
      .def_readonly("overrides", &LoadedScene::overrides, "the \"a.b=value\" overrides applied")
      .def_property_readonly(
          "name", [](const LoadedScene& s) { return s.scene.name; }, "the scene's name")
      .def_property_readonly(
          "particle_count", [](const LoadedScene& s) { return s.scene.particles.size(); },
          "P, its particles")
      .def_property_readonly(
          "frames", [](const LoadedScene& s) { return s.scene.settings.frames; },
          "frames a run writes after the initial state")
      .def_property_readonly(
          "substeps", [](const LoadedScene& s) { return s.scene.settings.substeps; },
          "MPM steps per frame")
      .def_property_readonly(
          "dt", [](const LoadedScene& s) { return s.scene.settings.dt; }, "the MPM step, s")
      .def_property_readonly(
          "dx", [](const LoadedScene& s) { return s.scene.settings.dx; }, "the grid's cell size, m")
      .def_property_readonly(
          "json", [](const LoadedScene& s) { return s.json.dump(); },
          "the scene as it runs (overrides and mu applied), as JSON text")
      .def_property_readonly(
          "sweep", [](const LoadedScene& s) { return sweep_dict(s.sweep); },
          "its \"sweep\" section as a dict (parameter, lo, hi, train, test), or None")
      .def_property_readonly(
          "colliders",
          [](const LoadedScene& s) {
            std::vector<std::string> types;
            for (const auto& c : s.scene.colliders) types.push_back(c->type());
            return types;
          },
          "the colliders' types (\"box\", \"plane\", ...), in its order")
      // The initial positions, P×3: a read-only view of the scene's own array, no copy.
      .def_property_readonly(
          "rest_positions",
          [](py::object self) {
            const std::vector<Vec3>& x = self.cast<const LoadedScene&>().scene.particles.X;
            py::array_t<double> view({x.size(), std::size_t(3)}, x.data()->data(), self);
            view.attr("setflags")(py::arg("write") = false);
            return view;
          },
          "the initial positions, (P, 3) float64, a read-only view of the scene's own array");
  m.def("_simulate", &simulate, py::arg("scene"), py::arg("out"), py::arg("threads") = 0);
}

}  // namespace nsf::python
