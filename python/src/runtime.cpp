// The reduced-order runtime (include/nsf/runtime.h, libnsf_runtime.so) as _nsf.Runtime; the
// Python class nsf.Rom wraps it. Positions, velocities, τ, C and the latent are written straight
// into a float32 numpy array: the caller's own (out=) or a new one, with no buffer in between.
#include <nsf/runtime.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bindings.h"

namespace py = pybind11;

namespace nsf::python {

namespace {

std::unique_ptr<Runtime> make_runtime(const std::string& model, const std::string& scene,
                                      std::optional<double> mu, long long samples,
                                      long long threads,
                                      const std::vector<std::string>& overrides) {
  check_input_path(model, "model file");
  check_input_path(scene, "scene file");
  check_mu(mu);
  check_samples(samples);
  check_threads(threads);
  RuntimeOptions options;
  options.mu = mu;
  options.samples = int(samples);
  options.threads = int(threads);
  options.overrides = overrides;
  py::gil_scoped_release nogil;
  return std::make_unique<Runtime>(model, scene, options);
}

// "(864, 3)", the way numpy writes a shape.
std::string shape_text(const std::vector<std::size_t>& shape) {
  std::string text = "(";
  for (std::size_t i = 0; i < shape.size(); ++i) text += (i ? ", " : "") + std::to_string(shape[i]);
  return text + (shape.size() == 1 ? ",)" : ")");
}

// `out` if it is a writeable, C-contiguous float32 array of `shape`, else a ValueError or
// TypeError saying what it must be; a new such array when `out` is None.
py::array_t<float> target(const std::vector<std::size_t>& shape, const py::object& out,
                          const char* what) {
  if (out.is_none()) return py::array_t<float>(shape);
  const std::string want = std::string(what) + ": out must be a writeable, C-contiguous float32 " +
                           "array of shape " + shape_text(shape) + ", e.g. np.empty(" +
                           shape_text(shape) + ", np.float32)";
  if (!py::isinstance<py::array>(out))
    throw py::type_error(want + "; got " + py::str(out.get_type()).cast<std::string>());
  const auto a = py::reinterpret_borrow<py::array>(out);
  bool same_shape = std::size_t(a.ndim()) == shape.size();
  for (std::size_t i = 0; same_shape && i < shape.size(); ++i)
    same_shape = std::size_t(a.shape(py::ssize_t(i))) == shape[i];
  std::string got;
  if (!a.dtype().equal(py::dtype::of<float>()))
    got = "dtype " + py::str(a.dtype()).cast<std::string>();
  else if (!same_shape)
    got = "shape " + py::str(out.attr("shape")).cast<std::string>();
  else if (!(a.flags() & py::array::c_style))
    got = "an array that is not C-contiguous";
  else if (!a.writeable())
    got = "a read-only array";
  if (!got.empty()) throw py::value_error(want + "; got " + got);
  return py::reinterpret_borrow<py::array_t<float>>(out);
}

// One of the runtime's float outputs (positions, velocities: 3 per particle; stress, affine: 9;
// latent: latent_dim) written into `out`, or a new array, with the GIL released.
using Output = void (Runtime::*)(float*, std::size_t) const;

template <Output get>
py::array_t<float> output(const Runtime& rt, const std::vector<std::size_t>& shape,
                          const py::object& out, const char* what) {
  py::array_t<float> a = target(shape, out, what);
  float* data = a.mutable_data();
  const std::size_t size = std::size_t(a.size());
  py::gil_scoped_release nogil;
  (rt.*get)(data, size);
  return a;
}

std::vector<std::size_t> vectors(const Runtime& rt) {
  return {rt.particle_count(), 3};
}
std::vector<std::size_t> matrices(const Runtime& rt) {
  return {rt.particle_count(), 3, 3};
}

py::dict health(const Runtime& rt) {
  const RuntimeHealth h = rt.health();
  py::dict d;
  d["indicator"] = h.indicator;
  d["misfit_cells"] = h.misfit_cells;
  d["courant"] = h.courant;
  d["grid_margin"] = h.grid_margin;
  d["flagged"] = h.flagged;
  d["recoveries"] = h.recoveries;
  d["last_recovery"] = h.last_recovery;
  d["outside_training"] = h.outside_training;
  d["steps_outside"] = h.steps_outside;
  d["training_note"] = h.training_note;
  return d;
}

}  // namespace

void bind_runtime(py::module_& m) {
  py::class_<ColliderPose>(m, "ColliderPose")
      .def(py::init<>())
      .def_readwrite("position", &ColliderPose::position)
      .def_readwrite("rotation", &ColliderPose::rotation)
      .def_readwrite("velocity", &ColliderPose::velocity)
      .def_readwrite("angular_velocity", &ColliderPose::angular_velocity);

  py::class_<ObjectPose>(m, "ObjectPose")
      .def_readonly("position", &ObjectPose::position)
      .def_readonly("rotation", &ObjectPose::rotation)
      .def_readonly("velocity", &ObjectPose::velocity)
      .def_readonly("angular_velocity", &ObjectPose::angular_velocity)
      .def_readonly("rest_position", &ObjectPose::rest_position)
      .def_readonly("misfit", &ObjectPose::misfit);

  py::class_<Runtime>(m, "Runtime")
      .def(py::init(&make_runtime), py::arg("model"), py::arg("scene"), py::arg("mu") = py::none(),
           py::arg("samples") = 0, py::arg("threads") = 0,
           py::arg("overrides") = std::vector<std::string>())
      .def_property_readonly("particle_count", &Runtime::particle_count)
      .def_property_readonly("frame_count", &Runtime::frame_count)
      .def_property_readonly("frame_time", &Runtime::frame_time)
      .def_property_readonly("steps_per_frame", &Runtime::steps_per_frame)
      .def_property_readonly("time", &Runtime::time)
      .def("advance_frame", &Runtime::advance_frame, py::call_guard<py::gil_scoped_release>())
      .def("step", &Runtime::step, py::call_guard<py::gil_scoped_release>())
      .def(
          "positions",
          [](const Runtime& rt, const py::object& out) {
            return output<&Runtime::positions>(rt, vectors(rt), out, "positions");
          },
          py::arg("out") = py::none())
      .def(
          "velocities",
          [](const Runtime& rt, const py::object& out) {
            return output<&Runtime::velocities>(rt, vectors(rt), out, "velocities");
          },
          py::arg("out") = py::none())
      .def(
          "stress",
          [](const Runtime& rt, const py::object& out) {
            return output<&Runtime::stress>(rt, matrices(rt), out, "stress");
          },
          py::arg("out") = py::none())
      .def(
          "affine",
          [](const Runtime& rt, const py::object& out) {
            return output<&Runtime::affine>(rt, matrices(rt), out, "affine");
          },
          py::arg("out") = py::none())
      .def_property_readonly("latent_dim", &Runtime::latent_dim)
      .def(
          "latent",
          [](const Runtime& rt, const py::object& out) {
            return output<&Runtime::latent>(rt, {rt.latent_dim()}, out, "latent");
          },
          py::arg("out") = py::none())
      .def("health", &health)
      .def_property_readonly("warnings", &Runtime::warnings)
      .def_property_readonly("object_count", &Runtime::object_count)
      .def("object_pose", &Runtime::object_pose)
      .def_property_readonly("collider_count", &Runtime::collider_count)
      .def("collider_type", &Runtime::collider_type)
      .def("collider_pose", &Runtime::collider_pose)
      .def("set_collider_pose", &Runtime::set_collider_pose);
}

}  // namespace nsf::python
