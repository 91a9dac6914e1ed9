// The C API (include/nsf/nsf.h) over the embedding API (include/nsf/runtime.h). Each call runs
// its body in `call`, which turns every exception into an nsf_status and the thread's last
// error message, so that none crosses into C.
#include <nsf/nsf.h>
#include <nsf/runtime.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <new>
#include <stdexcept>
#include <string>
#include <utility>

struct nsf_runtime {
  nsf::Runtime rt;
};

namespace {

// The last error of this thread, and whether setting it ran out of memory.
thread_local std::string last_error;
thread_local bool last_error_lost = false;

void set_error(const char* fn, const char* what) noexcept {
  last_error_lost = false;
  try {
    last_error = std::string(fn) + ": " + what;
  } catch (...) {
    last_error_lost = true;
  }
}

// An error the C layer finds itself, with its code.
struct Refused {
  nsf_status status;
  std::string message;
};

template <typename... A>
[[noreturn]] void refuse(nsf_status status, A&&... parts) {
  std::string m;
  ((m += std::string(std::forward<A>(parts))), ...);
  throw Refused{status, std::move(m)};
}

// "nsf::Runtime::step: x" -> "x": the C function's name stands in front instead.
const char* without_cpp_prefix(const char* what) {
  static const char prefix[] = "nsf::Runtime::";
  if (std::strncmp(what, prefix, sizeof prefix - 1) != 0) return what;
  const char* colon = std::strstr(what, ": ");
  return colon ? colon + 2 : what;
}

// Runs `body`; an exception becomes a status (`failed` for the runtime's own errors, which say
// what went wrong in their message) and the thread's last error.
template <typename F>
nsf_status call(const char* fn, nsf_status failed, F&& body) noexcept {
  try {
    body();
    last_error.clear();
    last_error_lost = false;
    return NSF_OK;
  } catch (const Refused& e) {
    set_error(fn, e.message.c_str());
    return e.status;
  } catch (const std::bad_alloc&) {
    set_error(fn, "out of memory");
    return NSF_ERROR_OUT_OF_MEMORY;
  } catch (const std::exception& e) {
    set_error(fn, without_cpp_prefix(e.what()));
    return failed;
  } catch (...) {
    set_error(fn, "an unknown exception");
    return NSF_ERROR_INTERNAL;
  }
}

void need(const void* p, const char* name) {
  if (!p) refuse(NSF_ERROR_NULL_POINTER, name, " is NULL");
}

const nsf::Runtime& runtime(const nsf_runtime* r) {
  need(r, "the runtime handle");
  return r->rt;
}
nsf::Runtime& runtime(nsf_runtime* r) {
  need(r, "the runtime handle");
  return r->rt;
}

void check_buffer(const void* out, std::size_t size, std::size_t needed, const char* unit) {
  need(out, "the buffer");
  if (size < needed)
    refuse(NSF_ERROR_BUFFER_TOO_SMALL, "the buffer holds ", std::to_string(size), " ", unit, ", ",
           std::to_string(needed), " are needed");
}

// Copies `text` into out[0, size) with its NUL, setting *length to its length; see nsf.h.
void write_text(const std::string& text, char* out, std::size_t size, std::size_t* length) {
  need(length, "length");
  *length = text.size();
  if (size == 0 && !out) return;
  need(out, "the buffer");
  if (size <= text.size())
    refuse(NSF_ERROR_BUFFER_TOO_SMALL, "the buffer holds ", std::to_string(size), " bytes, ",
           std::to_string(text.size() + 1), " are needed");
  std::memcpy(out, text.c_str(), text.size() + 1);
}

// Index `index` of one of `count` colliders or objects (`what`), else NSF_ERROR_INVALID_ARGUMENT.
void check_index(std::size_t index, std::size_t count, const char* what) {
  if (index >= count)
    refuse(NSF_ERROR_INVALID_ARGUMENT, what, " ", std::to_string(index),
           " does not exist: the scene has ", std::to_string(count));
}
void check_index(const nsf::Runtime& rt, std::size_t index) {
  check_index(index, rt.collider_count(), "collider");
}

void check_file(const char* path, const char* what) {
  need(path, what);
  std::error_code ec;
  if (!std::filesystem::exists(path, ec))
    refuse(NSF_ERROR_FILE_NOT_FOUND, "the ", what, " '", path, "' does not exist");
  if (std::filesystem::is_directory(path, ec))
    refuse(NSF_ERROR_FILE_NOT_FOUND, "the ", what, " '", path, "' is a directory, not a file");
}

nsf::RuntimeOptions to_cpp(const nsf_runtime_options& o) {
  nsf::RuntimeOptions r;
  if (o.has_mu) {
    if (!std::isfinite(o.mu)) refuse(NSF_ERROR_INVALID_ARGUMENT, "mu is not finite");
    r.mu = o.mu;
  }
  if (o.samples < 0)
    refuse(NSF_ERROR_INVALID_ARGUMENT, "samples must be 0 (the scene's) or more, got ",
           std::to_string(o.samples));
  if (o.threads < 0)
    refuse(NSF_ERROR_INVALID_ARGUMENT, "threads must be 0 (all cores) or more, got ",
           std::to_string(o.threads));
  r.samples = o.samples;
  r.threads = o.threads;
  if (o.override_count > 0) need(o.overrides, "options->overrides");
  for (std::size_t i = 0; i < o.override_count; ++i) {
    if (!o.overrides[i])
      refuse(NSF_ERROR_NULL_POINTER, "options->overrides[", std::to_string(i), "] is NULL");
    r.overrides.emplace_back(o.overrides[i]);
  }
  const std::pair<const char*, double> limits[] = {
      {"indicator_misfit_cells", o.indicator_misfit_cells},
      {"indicator_courant", o.indicator_courant},
      {"indicator_grid_margin", o.indicator_grid_margin}};
  for (const auto& [name, value] : limits)
    if (!(value > 0))  // +inf: no limit
      refuse(NSF_ERROR_INVALID_ARGUMENT, name, " must be a number above 0, got ",
             std::to_string(value));
  r.indicator_misfit_cells = o.indicator_misfit_cells;
  r.indicator_courant = o.indicator_courant;
  r.indicator_grid_margin = o.indicator_grid_margin;
  r.recover = o.recover != 0;
  return r;
}

nsf::ColliderPose to_cpp(const nsf_collider_pose& p) {
  nsf::ColliderPose r;
  for (int k = 0; k < 3; ++k) {
    r.position[k] = p.position[k];
    r.velocity[k] = p.velocity[k];
    r.angular_velocity[k] = p.angular_velocity[k];
  }
  for (int k = 0; k < 9; ++k) r.rotation[k] = p.rotation[k];
  return r;
}

}  // namespace

extern "C" {

const char* nsf_version(void) {
  return NSF_VERSION;
}

const char* nsf_build_arch(void) {
  return nsf::build_arch();
}

nsf_status nsf_version_numbers(int* major, int* minor, int* patch) {
  return call("nsf_version_numbers", NSF_ERROR_INTERNAL, [&] {
    need(major, "major");
    need(minor, "minor");
    need(patch, "patch");
    *major = NSF_VERSION_MAJOR;
    *minor = NSF_VERSION_MINOR;
    *patch = NSF_VERSION_PATCH;
  });
}

const char* nsf_last_error(void) {
  return last_error_lost ? "out of memory (while writing the error message)" : last_error.c_str();
}

const char* nsf_status_name(nsf_status status) {
  switch (status) {
    case NSF_OK:
      return "NSF_OK";
    case NSF_ERROR_NULL_POINTER:
      return "NSF_ERROR_NULL_POINTER";
    case NSF_ERROR_INVALID_ARGUMENT:
      return "NSF_ERROR_INVALID_ARGUMENT";
    case NSF_ERROR_BUFFER_TOO_SMALL:
      return "NSF_ERROR_BUFFER_TOO_SMALL";
    case NSF_ERROR_FILE_NOT_FOUND:
      return "NSF_ERROR_FILE_NOT_FOUND";
    case NSF_ERROR_SETUP:
      return "NSF_ERROR_SETUP";
    case NSF_ERROR_STEP:
      return "NSF_ERROR_STEP";
    case NSF_ERROR_OUT_OF_MEMORY:
      return "NSF_ERROR_OUT_OF_MEMORY";
    case NSF_ERROR_INTERNAL:
      return "NSF_ERROR_INTERNAL";
  }
  return "NSF_UNKNOWN_STATUS";
}

nsf_status nsf_runtime_options_init(nsf_runtime_options* options) {
  return call("nsf_runtime_options_init", NSF_ERROR_INTERNAL, [&] {
    need(options, "options");
    const nsf::RuntimeOptions d;
    *options = nsf_runtime_options{};
    options->has_mu = 0;
    options->mu = 0;
    options->samples = d.samples;
    options->threads = d.threads;
    options->overrides = nullptr;
    options->override_count = 0;
    options->indicator_misfit_cells = d.indicator_misfit_cells;
    options->indicator_courant = d.indicator_courant;
    options->indicator_grid_margin = d.indicator_grid_margin;
    options->recover = d.recover ? 1 : 0;
  });
}

nsf_status nsf_runtime_create(const char* model_path, const char* scene_path,
                              const nsf_runtime_options* options, nsf_runtime** out) {
  return call("nsf_runtime_create", NSF_ERROR_SETUP, [&] {
    need(out, "out");
    *out = nullptr;
    check_file(model_path, "model file");
    check_file(scene_path, "scene file");
    nsf_runtime_options defaults;
    if (!options) {
      nsf_runtime_options_init(&defaults);
      options = &defaults;
    }
    *out = new nsf_runtime{nsf::Runtime(model_path, scene_path, to_cpp(*options))};
  });
}

void nsf_runtime_destroy(nsf_runtime* runtime) {
  delete runtime;  // ~Runtime throws nothing
}

nsf_status nsf_runtime_particle_count(const nsf_runtime* r, size_t* out) {
  return call("nsf_runtime_particle_count", NSF_ERROR_INTERNAL, [&] {
    const nsf::Runtime& rt = runtime(r);
    need(out, "out");
    *out = rt.particle_count();
  });
}
nsf_status nsf_runtime_frame_count(const nsf_runtime* r, int* out) {
  return call("nsf_runtime_frame_count", NSF_ERROR_INTERNAL, [&] {
    const nsf::Runtime& rt = runtime(r);
    need(out, "out");
    *out = rt.frame_count();
  });
}
nsf_status nsf_runtime_frame_time(const nsf_runtime* r, double* out) {
  return call("nsf_runtime_frame_time", NSF_ERROR_INTERNAL, [&] {
    const nsf::Runtime& rt = runtime(r);
    need(out, "out");
    *out = rt.frame_time();
  });
}
nsf_status nsf_runtime_steps_per_frame(const nsf_runtime* r, int* out) {
  return call("nsf_runtime_steps_per_frame", NSF_ERROR_INTERNAL, [&] {
    const nsf::Runtime& rt = runtime(r);
    need(out, "out");
    *out = rt.steps_per_frame();
  });
}
nsf_status nsf_runtime_time(const nsf_runtime* r, double* out) {
  return call("nsf_runtime_time", NSF_ERROR_INTERNAL, [&] {
    const nsf::Runtime& rt = runtime(r);
    need(out, "out");
    *out = rt.time();
  });
}

nsf_status nsf_runtime_step(nsf_runtime* r) {
  return call("nsf_runtime_step", NSF_ERROR_STEP, [&] { runtime(r).step(); });
}
nsf_status nsf_runtime_advance_frame(nsf_runtime* r) {
  return call("nsf_runtime_advance_frame", NSF_ERROR_STEP, [&] { runtime(r).advance_frame(); });
}

nsf_status nsf_runtime_positions(const nsf_runtime* r, float* out, size_t size) {
  return call("nsf_runtime_positions", NSF_ERROR_INTERNAL, [&] {
    const nsf::Runtime& rt = runtime(r);
    check_buffer(out, size, 3 * rt.particle_count(), "floats");
    rt.positions(out, size);
  });
}
nsf_status nsf_runtime_velocities(const nsf_runtime* r, float* out, size_t size) {
  return call("nsf_runtime_velocities", NSF_ERROR_INTERNAL, [&] {
    const nsf::Runtime& rt = runtime(r);
    check_buffer(out, size, 3 * rt.particle_count(), "floats");
    rt.velocities(out, size);
  });
}
nsf_status nsf_runtime_stress(const nsf_runtime* r, float* out, size_t size) {
  return call("nsf_runtime_stress", NSF_ERROR_INTERNAL, [&] {
    const nsf::Runtime& rt = runtime(r);
    check_buffer(out, size, 9 * rt.particle_count(), "floats");
    rt.stress(out, size);
  });
}
nsf_status nsf_runtime_affine(const nsf_runtime* r, float* out, size_t size) {
  return call("nsf_runtime_affine", NSF_ERROR_INTERNAL, [&] {
    const nsf::Runtime& rt = runtime(r);
    check_buffer(out, size, 9 * rt.particle_count(), "floats");
    rt.affine(out, size);
  });
}

nsf_status nsf_runtime_latent_dim(const nsf_runtime* r, size_t* out) {
  return call("nsf_runtime_latent_dim", NSF_ERROR_INTERNAL, [&] {
    const nsf::Runtime& rt = runtime(r);
    need(out, "out");
    *out = rt.latent_dim();
  });
}
nsf_status nsf_runtime_latent(const nsf_runtime* r, float* out, size_t size) {
  return call("nsf_runtime_latent", NSF_ERROR_INTERNAL, [&] {
    const nsf::Runtime& rt = runtime(r);
    check_buffer(out, size, rt.latent_dim(), "floats");
    rt.latent(out, size);
  });
}

nsf_status nsf_runtime_health(const nsf_runtime* r, nsf_health* out) {
  return call("nsf_runtime_health", NSF_ERROR_INTERNAL, [&] {
    const nsf::Runtime& rt = runtime(r);
    need(out, "out");
    const nsf::RuntimeHealth h = rt.health();
    out->indicator = h.indicator;
    out->misfit_cells = h.misfit_cells;
    out->courant = h.courant;
    out->grid_margin = h.grid_margin;
    out->flagged = h.flagged ? 1 : 0;
    out->recoveries = int64_t(h.recoveries);
    out->outside_training = h.outside_training ? 1 : 0;
    out->steps_outside = int64_t(h.steps_outside);
  });
}
nsf_status nsf_runtime_last_recovery(const nsf_runtime* r, char* out, size_t size, size_t* length) {
  return call("nsf_runtime_last_recovery", NSF_ERROR_INTERNAL,
              [&] { write_text(runtime(r).health().last_recovery, out, size, length); });
}
nsf_status nsf_runtime_training_note(const nsf_runtime* r, char* out, size_t size, size_t* length) {
  return call("nsf_runtime_training_note", NSF_ERROR_INTERNAL,
              [&] { write_text(runtime(r).health().training_note, out, size, length); });
}
nsf_status nsf_runtime_warnings(const nsf_runtime* r, char* out, size_t size, size_t* length) {
  return call("nsf_runtime_warnings", NSF_ERROR_INTERNAL, [&] {
    std::string text;
    for (const std::string& w : runtime(r).warnings()) text += w + "\n";
    write_text(text, out, size, length);
  });
}

nsf_status nsf_runtime_object_count(const nsf_runtime* r, size_t* out) {
  return call("nsf_runtime_object_count", NSF_ERROR_INTERNAL, [&] {
    const nsf::Runtime& rt = runtime(r);
    need(out, "out");
    *out = rt.object_count();
  });
}
nsf_status nsf_runtime_object_pose(const nsf_runtime* r, size_t index, nsf_object_pose* out) {
  return call("nsf_runtime_object_pose", NSF_ERROR_INVALID_ARGUMENT, [&] {
    const nsf::Runtime& rt = runtime(r);
    need(out, "out");
    check_index(index, rt.object_count(), "object");
    const nsf::ObjectPose p = rt.object_pose(index);
    for (int k = 0; k < 3; ++k) {
      out->position[k] = p.position[k];
      out->velocity[k] = p.velocity[k];
      out->angular_velocity[k] = p.angular_velocity[k];
      out->rest_position[k] = p.rest_position[k];
    }
    for (int k = 0; k < 9; ++k) out->rotation[k] = p.rotation[k];
    out->misfit = p.misfit;
  });
}
nsf_status nsf_runtime_collider_count(const nsf_runtime* r, size_t* out) {
  return call("nsf_runtime_collider_count", NSF_ERROR_INTERNAL, [&] {
    const nsf::Runtime& rt = runtime(r);
    need(out, "out");
    *out = rt.collider_count();
  });
}
nsf_status nsf_runtime_collider_type(const nsf_runtime* r, size_t index, char* out, size_t size,
                                     size_t* length) {
  return call("nsf_runtime_collider_type", NSF_ERROR_INVALID_ARGUMENT, [&] {
    const nsf::Runtime& rt = runtime(r);
    check_index(rt, index);
    write_text(rt.collider_type(index), out, size, length);
  });
}
nsf_status nsf_runtime_collider_pose(const nsf_runtime* r, size_t index, nsf_collider_pose* out) {
  return call("nsf_runtime_collider_pose", NSF_ERROR_INVALID_ARGUMENT, [&] {
    const nsf::Runtime& rt = runtime(r);
    need(out, "out");
    check_index(rt, index);
    const nsf::ColliderPose p = rt.collider_pose(index);
    for (int k = 0; k < 3; ++k) {
      out->position[k] = p.position[k];
      out->velocity[k] = p.velocity[k];
      out->angular_velocity[k] = p.angular_velocity[k];
    }
    for (int k = 0; k < 9; ++k) out->rotation[k] = p.rotation[k];
  });
}
nsf_status nsf_runtime_set_collider_pose(nsf_runtime* r, size_t index,
                                         const nsf_collider_pose* pose) {
  // Runtime::set_collider_pose refuses a pose with std::runtime_error, the collider unchanged.
  return call("nsf_runtime_set_collider_pose", NSF_ERROR_INVALID_ARGUMENT, [&] {
    nsf::Runtime& rt = runtime(r);
    need(pose, "pose");
    check_index(rt, index);
    rt.set_collider_pose(index, to_cpp(*pose));
  });
}

}  // extern "C"
