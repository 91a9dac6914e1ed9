// The extension module behind `import nsf`: its parts, and nsf's errors as Python exceptions.
#include "bindings.h"

PYBIND11_MODULE(_nsf, m) {
  m.doc() = "nsf: full-order MPM runs, run files and the reduced-order runtime (docs/PYTHON.md)";
  m.attr("__version__") = NSF_VERSION;
  nsf::python::bind_scene(m);
  nsf::python::bind_run(m);
  nsf::python::bind_runtime(m);
}
