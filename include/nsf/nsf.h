/* nsf's C API: the embedding runtime (nsf::Runtime, <nsf/runtime.h>) behind opaque handles and
 * error codes, for hosts in C and for any language with a C foreign-function interface (Rust,
 * C#, Python's ctypes, ...). docs/EMBEDDING.md, "From C, Rust, C#".
 *
 * Every call but nsf_runtime_destroy, nsf_version, nsf_build_arch, nsf_status_name and
 * nsf_last_error returns an nsf_status: NSF_OK, or an error code whose message nsf_last_error()
 * gives on the same thread.
 * No C++ exception leaves a call; a NULL pointer or a buffer too small is an error code, never a
 * crash. A handle may be used by one thread at a time; different handles by different threads.
 * The header is C99 and C++; it holds standard C types only. */
#ifndef NSF_NSF_H
#define NSF_NSF_H

#include <stddef.h>
#include <stdint.h>

#if defined(__GNUC__)
#define NSF_C_API __attribute__((visibility("default")))
#else
#define NSF_C_API
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* What a call returns. The values are fixed: new codes are only ever added at the end. */
typedef enum nsf_status {
  NSF_OK = 0,
  NSF_ERROR_NULL_POINTER = 1,     /* a pointer the call needs was NULL */
  NSF_ERROR_INVALID_ARGUMENT = 2, /* a value refused: an index past the end, a negative count,
                                     an option out of range, a collider pose refused */
  NSF_ERROR_BUFFER_TOO_SMALL = 3, /* the caller's buffer holds fewer elements than needed */
  NSF_ERROR_FILE_NOT_FOUND = 4,   /* the model or scene file does not exist */
  NSF_ERROR_SETUP = 5,            /* the model, scene and options do not make a runtime: a file
                                     not readable as one, a model of another scene, mu missing
                                     or refused, an override that does not apply */
  NSF_ERROR_STEP = 6,             /* a step failed (with recover = 0: the dynamics diverged) */
  NSF_ERROR_OUT_OF_MEMORY = 7,    /* memory ran out (std::bad_alloc) */
  NSF_ERROR_INTERNAL = 8,         /* anything else (a bug: please report the message) */
} nsf_status;

/* A reduced-order simulator of one scene at one mu (nsf::Runtime). */
typedef struct nsf_runtime nsf_runtime;

/* How a run is set up (nsf::RuntimeOptions); nsf_runtime_options_init fills in the defaults. */
typedef struct nsf_runtime_options {
  int has_mu; /* nonzero: mu is the scene's sweep parameter mu (required when it has a sweep) */
  double mu;
  int samples; /* sample particles |S| of the latent fit; 0: the scene's "rom" section */
  int threads; /* threads of the MPM step and the networks; 0: all cores */
  /* "a.b.c=value" overrides of the scene, as `nsf rom --set` takes them: override_count strings
   * (copied by nsf_runtime_create; NULL when override_count is 0). */
  const char* const* overrides;
  size_t override_count;
  /* The error indicator's limits (docs/EMBEDDING.md, "Error indicator"), and recover: nonzero,
   * a step past them or one that diverges (a point off the grid, a latent not finite) is redone;
   * 0, the first is kept and flagged, the second fails with NSF_ERROR_STEP. */
  double indicator_misfit_cells; /* 0.5 */
  double indicator_courant;      /* 1 */
  double indicator_grid_margin;  /* 0.5 */
  int recover;                   /* 1 */
} nsf_runtime_options;

/* How the run is doing after the last step (nsf::RuntimeHealth; the text of the last recovery
 * is nsf_runtime_last_recovery's). */
typedef struct nsf_health {
  double indicator;    /* below 1 fine, 1 or more past a limit */
  double misfit_cells; /* the inversion's rms misfit at the samples, in cells */
  double courant;      /* the fastest integration point's cells per step */
  double grid_margin;  /* cells left before the grid's edge */
  int flagged;         /* nonzero: the last step's indicator was 1 or more, or it was redone */
  int64_t recoveries;  /* steps redone so far */
  /* nonzero: in the last step a collider was outside the model's training box (more than a cell
   * beyond where its training runs moved it, or faster); nsf_runtime_training_note says what */
  int outside_training;
  int64_t steps_outside; /* steps so far that were */
} nsf_health;

/* A rigid collider's pose in the world frame (nsf::ColliderPose). */
typedef struct nsf_collider_pose {
  double position[3];         /* its reference point, m */
  double rotation[9];         /* body -> world, row-major */
  double velocity[3];         /* of that point, m/s */
  double angular_velocity[3]; /* rad/s, about that point */
} nsf_collider_pose;

/* A scene object's motion as a rigid body, fitted to its particles now (nsf::ObjectPose): a rest
 * point X sits near rotation * (X - rest_position) + position. */
typedef struct nsf_object_pose {
  double position[3];         /* centre of mass now, m */
  double rotation[9];         /* rest -> now, row-major */
  double velocity[3];         /* of the centre of mass, m/s */
  double angular_velocity[3]; /* rad/s, about the centre of mass */
  double rest_position[3];    /* centre of mass at rest, m */
  double misfit;              /* rms distance (m) of the particles from that rigid copy */
} nsf_object_pose;

/* The library's version, "MAJOR.MINOR.PATCH", and its numbers. */
NSF_C_API const char* nsf_version(void);
NSF_C_API nsf_status nsf_version_numbers(int* major, int* minor, int* patch);
/* The instruction set this copy of the library was built for: "x86-64-v2" (the baseline copy),
 * "x86-64-v3" (the copy the loader picks on a CPU with AVX2 and FMA) or "native". */
NSF_C_API const char* nsf_build_arch(void);

/* The message of the last nsf_ call made on this thread: "" when it succeeded. Valid until the
 * thread's next nsf_ call; never NULL. */
NSF_C_API const char* nsf_last_error(void);
/* The enumerator's name ("NSF_ERROR_BUFFER_TOO_SMALL"); "NSF_UNKNOWN_STATUS" for another value. */
NSF_C_API const char* nsf_status_name(nsf_status status);

/* The defaults of nsf::RuntimeOptions: no mu, samples and threads 0, no overrides, the
 * indicator's limits 0.5, 1, 0.5, recover 1. */
NSF_C_API nsf_status nsf_runtime_options_init(nsf_runtime_options* options);

/* Loads the model (a .nsf file of `nsf train`) and the scene JSON it was trained on, applies mu
 * and the overrides, and sets up the run at the scene's initial state. `options` NULL: the
 * defaults. On success *out is a new handle, for nsf_runtime_destroy; on failure it is NULL. */
NSF_C_API nsf_status nsf_runtime_create(const char* model_path, const char* scene_path,
                                        const nsf_runtime_options* options, nsf_runtime** out);
/* Frees the handle; NULL is ignored. */
NSF_C_API void nsf_runtime_destroy(nsf_runtime* runtime);

NSF_C_API nsf_status nsf_runtime_particle_count(const nsf_runtime* runtime, size_t* out);
/* The scene's frames (the run may go on past them), seconds per frame, ROM steps per frame, and
 * the simulated seconds so far. */
NSF_C_API nsf_status nsf_runtime_frame_count(const nsf_runtime* runtime, int* out);
NSF_C_API nsf_status nsf_runtime_frame_time(const nsf_runtime* runtime, double* out);
NSF_C_API nsf_status nsf_runtime_steps_per_frame(const nsf_runtime* runtime, int* out);
NSF_C_API nsf_status nsf_runtime_time(const nsf_runtime* runtime, double* out);

/* One reduced-order step; one frame (steps_per_frame steps). */
NSF_C_API nsf_status nsf_runtime_step(nsf_runtime* runtime);
NSF_C_API nsf_status nsf_runtime_advance_frame(nsf_runtime* runtime);

/* Per-particle state into the caller's buffer of `size` floats: NSF_ERROR_BUFFER_TOO_SMALL (the
 * buffer untouched) when it holds fewer than the per-particle count times particle_count.
 * positions: x0 y0 z0 x1 ..., m (3 per particle). velocities: the same, m/s, the backward
 * difference of the last step. stress: the Kirchhoff stress tau (= J sigma, Pa) of every particle,
 * 3x3 row-major (9 per particle), from the source the ROM step itself uses for tau (the trained
 * decoder, or the tracked state of rom.fields.stress = "tracked"), at the current latent. affine:
 * the affine velocity C (1/s) of every particle, 3x3 row-major, from the source the step takes C
 * from (zero with rom.fields.affine = "none"). */
NSF_C_API nsf_status nsf_runtime_positions(const nsf_runtime* runtime, float* out, size_t size);
NSF_C_API nsf_status nsf_runtime_velocities(const nsf_runtime* runtime, float* out, size_t size);
NSF_C_API nsf_status nsf_runtime_stress(const nsf_runtime* runtime, float* out, size_t size);
NSF_C_API nsf_status nsf_runtime_affine(const nsf_runtime* runtime, float* out, size_t size);

/* The latent z_n of the run now (latent_dim floats): what `nsf serve` streams. */
NSF_C_API nsf_status nsf_runtime_latent_dim(const nsf_runtime* runtime, size_t* out);
NSF_C_API nsf_status nsf_runtime_latent(const nsf_runtime* runtime, float* out, size_t size);

/* The health after the last step; the text of the last recovery ("" for none) into `out` of
 * `size` bytes, NUL-terminated. *length gets the text's length (without the NUL) in every case;
 * `out` may be NULL when `size` is 0, to ask for the length alone; else a `size` of length or
 * less is NSF_ERROR_BUFFER_TOO_SMALL. */
NSF_C_API nsf_status nsf_runtime_health(const nsf_runtime* runtime, nsf_health* out);
NSF_C_API nsf_status nsf_runtime_last_recovery(const nsf_runtime* runtime, char* out, size_t size,
                                               size_t* length);
/* What lay outside the training box the first time a step was ("" while none has), written as
 * nsf_runtime_last_recovery writes its text. */
NSF_C_API nsf_status nsf_runtime_training_note(const nsf_runtime* runtime, char* out, size_t size,
                                               size_t* length);
/* What the set-up warned of (Runtime::warnings: μ outside the training range, a scene outside
 * the model's training family), one line each ending in '\n' ("" for none), written as
 * nsf_runtime_last_recovery writes its text. */
NSF_C_API nsf_status nsf_runtime_warnings(const nsf_runtime* runtime, char* out, size_t size,
                                          size_t* length);

/* The scene's objects, in the order of its "objects" list, each fitted as a rigid body
 * (Runtime::object_pose; the first call after a step decodes every particle). An index past the
 * end is NSF_ERROR_INVALID_ARGUMENT. */
NSF_C_API nsf_status nsf_runtime_object_count(const nsf_runtime* runtime, size_t* out);
NSF_C_API nsf_status nsf_runtime_object_pose(const nsf_runtime* runtime, size_t index,
                                             nsf_object_pose* out);

/* The scene's colliders, in the order of its "colliders" list. The type ("box", "cylinder",
 * "plane") is written as nsf_runtime_last_recovery writes its text (16 bytes always suffice). */
NSF_C_API nsf_status nsf_runtime_collider_count(const nsf_runtime* runtime, size_t* out);
NSF_C_API nsf_status nsf_runtime_collider_type(const nsf_runtime* runtime, size_t index, char* out,
                                               size_t size, size_t* length);
NSF_C_API nsf_status nsf_runtime_collider_pose(const nsf_runtime* runtime, size_t index,
                                               nsf_collider_pose* out);
/* The host takes collider `index` over: it is at `pose` now and moves on with the pose's
 * velocities until the next call (its scripted motion is ignored from now on). A pose with a
 * value not finite, a rotation that is not one, or a position or velocity out of the scene's
 * bounds is NSF_ERROR_INVALID_ARGUMENT, the collider left as it was (docs/EMBEDDING.md). */
NSF_C_API nsf_status nsf_runtime_set_collider_pose(nsf_runtime* runtime, size_t index,
                                                   const nsf_collider_pose* pose);

#ifdef __cplusplus
} /* extern "C" */
#endif

#endif /* NSF_NSF_H */
