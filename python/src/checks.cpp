// The command line's checks on the module's arguments, as Python exceptions (docs/PYTHON.md,
// "Errors"): a count or thread number out of the CLI's range, a μ that is not finite, a path that
// is not a file. Made before anything runs, so that no argument reaches OpenMP, the engine or a
// file read unchecked: 10**9 threads made libgomp abort the interpreter, /dev/zero as a scene hung
// it.
#include <Python.h>

#include <cmath>
#include <string>

#include "bindings.h"
#include "core/input_file.h"

namespace py = pybind11;

namespace nsf::python {

namespace {

[[noreturn]] void raise(PyObject* type, const std::string& message) {
  PyErr_SetString(type, message.c_str());
  throw py::error_already_set();
}

}  // namespace

void check_threads(long long threads) {
  if (threads < 0 || threads > kMaxThreads)
    raise(PyExc_ValueError, "threads must be 0 to " + std::to_string(kMaxThreads) +
                                " (0: all cores), got " + std::to_string(threads) +
                                " (as -j takes it)");
}

void check_mu(const std::optional<double>& mu) {
  if (mu && !(std::isfinite(*mu) && std::abs(*mu) <= 1e300))
    raise(PyExc_ValueError, "mu must be a finite number (-1e300 to 1e300), got " +
                                py::str(py::float_(*mu)).cast<std::string>() +
                                " (as --mu takes it)");
}

void check_samples(long long samples) {
  if (samples < 0 || samples > 100000000)
    raise(PyExc_ValueError,
          "samples must be 0 (the scene's \"rom\" section) or 1 to 100000000, got " +
              std::to_string(samples) + " (as --samples takes it)");
}

void check_input_path(const std::string& path, const char* what) {
  const std::string kind = non_regular_kind(path);
  if (kind == "a directory")
    raise(PyExc_IsADirectoryError, std::string(what) + " " + path + " is a directory");
  if (!kind.empty())
    raise(PyExc_OSError,
          std::string(what) + " " + path + " is not a regular file (it is " + kind + ")");
  if (!py::module_::import("os").attr("path").attr("isfile")(path).cast<bool>())
    raise(PyExc_FileNotFoundError, std::string(what) + " " + path + ": no such file");
}

}  // namespace nsf::python
