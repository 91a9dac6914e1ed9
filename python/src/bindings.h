#pragma once
// The parts of the Python module _nsf (python/nsf/__init__.py wraps it; docs/PYTHON.md), one
// file each.
#include <pybind11/pybind11.h>

#include <optional>
#include <string>

namespace nsf::python {

void bind_scene(pybind11::module_& m);    // load_scene, simulate (scene.cpp)
void bind_run(pybind11::module_& m);      // read_run (run.cpp)
void bind_runtime(pybind11::module_& m);  // Rom, over nsf::Runtime (runtime.cpp)

// The command line's checks on the arguments (checks.cpp), each raising ValueError, or an OSError
// for a path, that names the argument and its range.
constexpr long long kMaxThreads = 1024;  // as -j
void check_threads(long long threads);
void check_mu(const std::optional<double>& mu);
void check_samples(long long samples);
// FileNotFoundError, IsADirectoryError, or OSError for a device, a socket or a pipe (whose open
// would wait for a writer, holding the interpreter); `what` names the argument ("scene file").
void check_input_path(const std::string& path, const char* what);

}  // namespace nsf::python
