// The extension module behind `import nsf`: its parts, and nsf's errors as Python exceptions.
#include "bindings.h"

#include <nsf/runtime.h>

PYBIND11_MODULE(_nsf, m) {
  m.doc() = "nsf: full-order MPM runs, run files and the reduced-order runtime (docs/PYTHON.md)";
  m.attr("__version__") = NSF_VERSION;
  m.def("build_arch", &nsf::build_arch,
        "The instruction set of the libnsf_runtime copy the loader took: \"x86-64-v2\", "
        "\"x86-64-v3\" (on a CPU with AVX2 and FMA, the copy built for it) or \"native\".");
  nsf::python::bind_scene(m);
  nsf::python::bind_run(m);
  nsf::python::bind_runtime(m);
}
