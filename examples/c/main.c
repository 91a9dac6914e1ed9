/* Embedding nsf from C (include/nsf/nsf.h): load a trained model and its scene, step the
 * reduced-order model frame by frame while the host raises collider 0, print the particles'
 * centroid and the run's health each frame, and show the error path (a model file that does not
 * exist). Usage: c_host MODEL SCENE MU [LIFT]: LIFT (m/s, default 0.5) raises collider 0 at
 * that speed; 0 holds it where it starts. examples/rust/ does the same from Rust. */
#include <nsf/nsf.h>
#include <stdio.h>
#include <stdlib.h>

/* Prints the failed call, its code and nsf's message, and leaves main. */
#define CHECK(call)                                                                               \
  do {                                                                                            \
    nsf_status status_ = (call);                                                                  \
    if (status_ != NSF_OK) {                                                                      \
      fprintf(stderr, "c_host: %s: %s (%d): %s\n", #call, nsf_status_name(status_), (int)status_, \
              nsf_last_error());                                                                  \
      goto fail;                                                                                  \
    }                                                                                             \
  } while (0)

int main(int argc, char** argv) {
  nsf_runtime_options options;
  nsf_runtime* rom = NULL;
  nsf_runtime* missing = NULL;
  nsf_collider_pose pose;
  nsf_object_pose body;
  nsf_health health;
  nsf_status status;
  float* x = NULL;
  float* tau = NULL;
  float* z = NULL;
  size_t particles = 0, latent_dim = 0, colliders = 0, length = 0, p;
  int frames = 0, steps = 0, frame, major = 0, minor = 0, patch = 0;
  double frame_time = 0, time = 0, y0, lift;
  char type[16];

  if (argc < 4) {
    fprintf(stderr, "usage: %s MODEL SCENE MU [LIFT]\n", argv[0]);
    return 2;
  }
  lift = argc > 4 ? atof(argv[4]) : 0.5;
  CHECK(nsf_version_numbers(&major, &minor, &patch));
  printf("nsf %s (%d.%d.%d)\n", nsf_version(), major, minor, patch);

  /* The error path: a model file that does not exist is a code and a message, not a crash. */
  status = nsf_runtime_create("no/such/model.nsf", argv[2], NULL, &missing);
  printf("missing model: %s, %s\n", nsf_status_name(status), nsf_last_error());
  if (status == NSF_OK || missing != NULL) {
    fprintf(stderr, "c_host: a missing model made a runtime\n");
    goto fail;
  }

  CHECK(nsf_runtime_options_init(&options));
  options.has_mu = 1;
  options.mu = atof(argv[3]);
  options.threads = 2;
  CHECK(nsf_runtime_create(argv[1], argv[2], &options, &rom));

  CHECK(nsf_runtime_particle_count(rom, &particles));
  CHECK(nsf_runtime_frame_count(rom, &frames));
  CHECK(nsf_runtime_frame_time(rom, &frame_time));
  CHECK(nsf_runtime_steps_per_frame(rom, &steps));
  CHECK(nsf_runtime_latent_dim(rom, &latent_dim));
  CHECK(nsf_runtime_collider_count(rom, &colliders));
  if (colliders == 0) {
    fprintf(stderr, "c_host: the scene has no collider to move\n");
    goto fail;
  }
  CHECK(nsf_runtime_collider_type(rom, 0, type, sizeof type, &length));
  CHECK(nsf_runtime_collider_pose(rom, 0, &pose));
  y0 = pose.position[1];
  printf("%zu particles, %d frames of %.4f s, %d steps each, latent of %zu, collider 0: %s\n",
         particles, frames, frame_time, steps, latent_dim, type);

  x = malloc(3 * particles * sizeof *x); /* the host's own buffers */
  tau = malloc(9 * particles * sizeof *tau);
  z = malloc(latent_dim * sizeof *z);
  if (!x || !tau || !z) {
    fprintf(stderr, "c_host: out of memory\n");
    goto fail;
  }

  for (frame = 1; frame <= frames; ++frame) {
    double c[3] = {0, 0, 0};
    CHECK(nsf_runtime_time(rom, &time));
    pose.position[1] = y0 + lift * time; /* the host moves collider 0 ... */
    pose.velocity[1] = lift;             /* ... and says how fast it goes */
    CHECK(nsf_runtime_set_collider_pose(rom, 0, &pose));
    CHECK(nsf_runtime_advance_frame(rom));

    CHECK(nsf_runtime_positions(rom, x, 3 * particles));
    CHECK(nsf_runtime_health(rom, &health));
    CHECK(nsf_runtime_time(rom, &time));
    for (p = 0; p < particles; ++p) {
      c[0] += x[3 * p];
      c[1] += x[3 * p + 1];
      c[2] += x[3 * p + 2];
    }
    printf(
        "frame %2d  t %.4f  centroid %.6f %.6f %.6f  indicator %.4f  flagged %d  recoveries %lld\n",
        frame, time, c[0] / (double)particles, c[1] / (double)particles, c[2] / (double)particles,
        health.indicator, health.flagged, (long long)health.recoveries);
  }

  /* The stress and the latent at the last frame; a buffer one float short is refused. */
  CHECK(nsf_runtime_stress(rom, tau, 9 * particles));
  CHECK(nsf_runtime_latent(rom, z, latent_dim));
  printf("tau of particle 0: %.3f %.3f %.3f (diagonal, Pa); z0 %.6f\n", tau[0], tau[4], tau[8],
         z[0]);
  /* Object 0 as a rigid body: its centre of mass, velocity and rigid-fit misfit. */
  CHECK(nsf_runtime_object_pose(rom, 0, &body));
  printf("object 0: centre %.6f %.6f %.6f  velocity %.6f %.6f %.6f  misfit %.6f m\n",
         body.position[0], body.position[1], body.position[2], body.velocity[0], body.velocity[1],
         body.velocity[2], body.misfit);
  status = nsf_runtime_positions(rom, x, 3 * particles - 1);
  printf("short buffer: %s, %s\n", nsf_status_name(status), nsf_last_error());
  if (status != NSF_ERROR_BUFFER_TOO_SMALL) goto fail;

  nsf_runtime_destroy(rom);
  free(x);
  free(tau);
  free(z);
  return 0;

fail:
  nsf_runtime_destroy(rom);
  free(x);
  free(tau);
  free(z);
  return 1;
}
