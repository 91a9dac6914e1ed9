// read_run: a run file (docs/OUTPUT.md) as numpy arrays. Each per-frame field is read by HDF5
// straight into the array numpy allocated for it, in one read; C and F come as frames × P × 3 × 3
// views of the stored rows, τ as stored (xx yy zz xy yz xz).
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cstring>
#include <string>
#include <vector>

#include "bindings.h"
#include "io/run_reader.h"

namespace py = pybind11;

namespace nsf::python {

namespace {

static_assert(sizeof(Vec3) == 3 * sizeof(double), "a std::vector<Vec3> is a P×3 array");

template <typename T>
py::array_t<T> copy_of(const std::vector<T>& v) {
  py::array_t<T> a(v.size());
  if (!v.empty()) std::memcpy(a.mutable_data(), v.data(), v.size() * sizeof(T));
  return a;
}

py::object attribute(const RunReader& r, const std::string& name) {
  switch (r.attribute_kind(name)) {
    case RunReader::AttributeKind::Integer:
      return py::int_(r.attribute_int(name));
    case RunReader::AttributeKind::Float:
      return py::float_(r.attribute_double(name));
    case RunReader::AttributeKind::String:
      return py::str(r.attribute_string(name));
    default:
      return py::none();  // a kind nsf never writes
  }
}

// `fields`: which of x, v, C, F, tau to read (all the others are small and always read).
py::dict read_run(const std::string& path, const std::vector<std::string>& fields) {
  check_input_path(path, "run file");
  const RunReader r(path);
  const std::size_t F = r.frame_count(), P = r.particle_count();
  py::dict out;
  for (const std::string& field : fields) {
    const std::size_t width = RunReader::frame_field_width(field);
    py::array_t<double> a({F, P, width});
    r.read_all_frames(field, a.mutable_data(), std::size_t(a.size()));
    out[field.c_str()] = width == 9 ? a.reshape({F, P, std::size_t(3), std::size_t(3)}) : a;
  }
  out["time"] = copy_of(r.times());
  py::array_t<double> X({P, std::size_t(3)});
  std::memcpy(X.mutable_data(), r.rest_positions().data(), 3 * P * sizeof(double));
  out["X"] = X;
  out["mass"] = copy_of(r.mass());
  out["volume"] = copy_of(r.volume());
  out["material"] = copy_of(r.material());
  out["object"] = copy_of(r.object());
  if (r.has_dataset("/rom/latent")) {
    std::size_t rows = 0, cols = 0;
    const std::vector<double> latent = r.read_table("/rom/latent", rows, cols);
    out["latent"] = copy_of(latent).reshape({rows, cols});
  }
  py::dict attrs;
  for (const std::string& name : r.attribute_names()) attrs[name.c_str()] = attribute(r, name);
  out["attrs"] = attrs;
  return out;
}

}  // namespace

void bind_run(py::module_& m) {
  m.def("_read_run", &read_run, py::arg("path"), py::arg("fields"));
  m.def("_frame_fields", [] { return std::vector<std::string>{"x", "v", "C", "F", "tau"}; });
}

}  // namespace nsf::python
