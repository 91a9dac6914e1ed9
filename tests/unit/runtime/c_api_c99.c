/* The C API's header as C99 sees it (built with -std=c99 -pedantic -Werror, CMakeLists.txt):
 * one run from C, for tests/unit/runtime/test_c_api.cpp. */
#include <nsf/nsf.h>
#include <stdio.h>

/* Loads MODEL and SCENE at mu 1, steps one frame, reads every position into a C array, and
 * returns the first failed call's status (NSF_OK for none), its message in `message`. */
int nsf_test_c99_run(const char* model, const char* scene, char* message, size_t size) {
  static float x[3 * 100000];
  nsf_runtime_options options;
  nsf_runtime* rom = NULL;
  size_t particles = 0;
  nsf_status status = nsf_runtime_options_init(&options);
  options.has_mu = 1;
  options.mu = 1.0;
  options.threads = 2;
  if (status == NSF_OK) status = nsf_runtime_create(model, scene, &options, &rom);
  if (status == NSF_OK) status = nsf_runtime_particle_count(rom, &particles);
  if (status == NSF_OK) status = nsf_runtime_advance_frame(rom);
  if (status == NSF_OK) status = nsf_runtime_positions(rom, x, sizeof x / sizeof x[0]);
  snprintf(message, size, "%s", nsf_last_error());
  nsf_runtime_destroy(rom);
  return (int)status;
}
