#pragma once
/* The C boundary between libnsf_runtime.so and the MLP plugin, libnsf_mlp.so (src/plugin/): the
 * one table of functions through which the torch-free runtime evaluates an MLP model's networks
 * (what nn/coordinate_networks.h declares), which need LibTorch. docs/EMBEDDING.md, "MLP models".
 *
 * Plain C on purpose: the runtime is also built for x86-64-v3 (cmake/hwcaps.cmake), where Eigen
 * allocates through its own aligned malloc, so no Eigen or standard-library object may be made on
 * one side and resized or freed on the other, and no C++ exception may cross. Across it go only
 * raw arrays of doubles in buffers the caller owns and sizes, opaque handles that the plugin makes
 * and frees, and error messages copied into the caller's nsf_mlp_error.
 *
 * Every function that can fail returns 0 on success, and otherwise non-zero with the reason in
 * `error->message` (NUL-terminated, cut to fit). A latent is `r` doubles (r: the model's latent
 * dimension, in its run-time record). Positions are x y z per point; 3x3 matrices 9 doubles per
 * point, row-major. `ids` index the prepared points; NULL is every prepared point, in order, and
 * then `n` is their count: `n` is always the number of points whose results the buffer holds. */
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Raised whenever the table changes in any way; the runtime refuses a plugin of another. */
#define NSF_MLP_PLUGIN_ABI_VERSION 1
/* The plugin's one exported symbol: a function returning its table. */
#define NSF_MLP_PLUGIN_ENTRY "nsf_mlp_plugin_table"

typedef struct nsf_mlp_error {
  char message[1024];
} nsf_mlp_error;

typedef struct nsf_mlp_model nsf_mlp_model;     /* a loaded model (the plugin's) */
typedef struct nsf_mlp_points nsf_mlp_points;   /* rest positions, prepared */
typedef struct nsf_mlp_samples nsf_mlp_samples; /* g at sample points, for the inversion */

typedef struct nsf_mlp_plugin {
  uint32_t abi_version;    /* NSF_MLP_PLUGIN_ABI_VERSION */
  uint32_t size;           /* sizeof(nsf_mlp_plugin) */
  const char* nsf_version; /* the nsf it was built from ("MAJOR.MINOR.PATCH") */

  /* Loads model file `path` (an MLP model) into *model. */
  int (*open)(const char* path, nsf_mlp_model** model, nsf_mlp_error* error);
  void (*close)(nsf_mlp_model* model); /* NULL is fine */
  /* The model's run-time record as nn/model_record.h encodes it (encode_model_record), which
   * an MLP model's file does not hold: `*size` is its byte count; `out` NULL asks for that alone,
   * else `capacity` bytes must hold it. */
  int (*record)(const nsf_mlp_model* model, unsigned char* out, size_t capacity, size_t* size,
                nsf_mlp_error* error);
  /* The encoder's kind ("network" or "modes"), cut to fit `capacity` bytes with its NUL. */
  int (*encoder_kind)(const nsf_mlp_model* model, char* out, size_t capacity, nsf_mlp_error* error);
  /* The networks' threads (the tool's set_nn_threads; threads > 0). */
  void (*set_threads)(int threads);

  /* e(x) of `frames` whole frames of `particles` positions each (x: 3 * particles doubles a
   * frame) into z, r doubles a frame. */
  int (*encode)(const nsf_mlp_model* model, const double* x, size_t frames, size_t particles,
                double* z, nsf_mlp_error* error);

  /* `count` rest positions X (3 * count doubles) prepared for the calls below. */
  int (*prepare)(const nsf_mlp_model* model, const double* X, size_t count, nsf_mlp_points** points,
                 nsf_mlp_error* error);
  void (*free_points)(nsf_mlp_points* points); /* NULL is fine */

  /* g at the points `ids` (n of them) for each of the `latents` latents in z (r doubles each),
   * into x: 3 * n doubles per latent, in the latents' order. */
  int (*deform)(const nsf_mlp_model* model, const nsf_mlp_points* points, const uint32_t* ids,
                size_t n, const double* z, size_t latents, double* x, nsf_mlp_error* error);
  /* h (τ) and l (C) at the points `ids` for one latent z, into 9 * n doubles. */
  int (*stress)(const nsf_mlp_model* model, const nsf_mlp_points* points, const uint32_t* ids,
                size_t n, const double* z, double mu, double* tau, nsf_mlp_error* error);
  int (*affine)(const nsf_mlp_model* model, const nsf_mlp_points* points, const uint32_t* ids,
                size_t n, const double* z, double* C, nsf_mlp_error* error);
  /* F = ∂g/∂X at the points `ids` (never NULL here) for z, into 9 * n doubles. */
  int (*deformation_gradients)(const nsf_mlp_model* model, const nsf_mlp_points* points,
                               const uint32_t* ids, size_t n, const double* z, double* F,
                               nsf_mlp_error* error);

  /* g at the points `ids` (never NULL here), kept for repeated evaluation: the inversion's. */
  int (*samples)(const nsf_mlp_model* model, const nsf_mlp_points* points, const uint32_t* ids,
                 size_t n, nsf_mlp_samples** samples, nsf_mlp_error* error);
  void (*free_samples)(nsf_mlp_samples* samples); /* NULL is fine */
  /* g at the samples for z, into 3n doubles. */
  int (*sample_values)(nsf_mlp_samples* samples, const double* z, double* g, nsf_mlp_error* error);
  /* g into 3n doubles and ∂g/∂ẑ into J, 3n × r column-major (row 3p + c: component c of sample
   * p). */
  int (*sample_jacobian)(nsf_mlp_samples* samples, const double* z, double* J, double* g,
                         nsf_mlp_error* error);
} nsf_mlp_plugin;

/* The type of the entry point, NSF_MLP_PLUGIN_ENTRY. */
typedef const nsf_mlp_plugin* (*nsf_mlp_plugin_entry)(void);

#ifdef __cplusplus
}
#endif
