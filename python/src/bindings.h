#pragma once
// The parts of the Python module _nsf (python/nsf/__init__.py wraps it; docs/PYTHON.md), one
// file each.
#include <pybind11/pybind11.h>

namespace nsf::python {

void bind_scene(pybind11::module_& m);    // load_scene, simulate (scene.cpp)
void bind_run(pybind11::module_& m);      // read_run (run.cpp)
void bind_runtime(pybind11::module_& m);  // Rom, over nsf::Runtime (runtime.cpp)

}  // namespace nsf::python
