//! The C API of include/nsf/nsf.h, declared by hand: the same names, the same layouts.
#![allow(non_camel_case_types)]

use std::os::raw::{c_char, c_int};

/// `nsf_status`: an int, so that a code this file does not know yet is still a valid value.
pub type nsf_status = c_int;
pub const NSF_OK: nsf_status = 0;
pub const NSF_ERROR_NULL_POINTER: nsf_status = 1;
pub const NSF_ERROR_INVALID_ARGUMENT: nsf_status = 2;
pub const NSF_ERROR_BUFFER_TOO_SMALL: nsf_status = 3;
pub const NSF_ERROR_FILE_NOT_FOUND: nsf_status = 4;
pub const NSF_ERROR_SETUP: nsf_status = 5;
pub const NSF_ERROR_STEP: nsf_status = 6;
pub const NSF_ERROR_OUT_OF_MEMORY: nsf_status = 7;
pub const NSF_ERROR_INTERNAL: nsf_status = 8;

/// The opaque `nsf_runtime`.
#[repr(C)]
pub struct nsf_runtime {
    _private: [u8; 0],
}

#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct nsf_runtime_options {
    pub has_mu: c_int,
    pub mu: f64,
    pub samples: c_int,
    pub threads: c_int,
    pub overrides: *const *const c_char,
    pub override_count: usize,
    pub indicator_misfit_cells: f64,
    pub indicator_courant: f64,
    pub indicator_grid_margin: f64,
    pub recover: c_int,
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct nsf_health {
    pub indicator: f64,
    pub misfit_cells: f64,
    pub courant: f64,
    pub grid_margin: f64,
    pub flagged: c_int,
    pub recoveries: i64,
    pub outside_training: c_int,
    pub steps_outside: i64,
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct nsf_collider_pose {
    pub position: [f64; 3],
    pub rotation: [f64; 9],
    pub velocity: [f64; 3],
    pub angular_velocity: [f64; 3],
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct nsf_object_pose {
    pub position: [f64; 3],
    pub rotation: [f64; 9],
    pub velocity: [f64; 3],
    pub angular_velocity: [f64; 3],
    pub rest_position: [f64; 3],
    pub misfit: f64,
}

extern "C" {
    pub fn nsf_version() -> *const c_char;
    pub fn nsf_version_numbers(
        major: *mut c_int,
        minor: *mut c_int,
        patch: *mut c_int,
    ) -> nsf_status;
    pub fn nsf_last_error() -> *const c_char;
    pub fn nsf_status_name(status: nsf_status) -> *const c_char;

    pub fn nsf_runtime_options_init(options: *mut nsf_runtime_options) -> nsf_status;
    pub fn nsf_runtime_create(
        model_path: *const c_char,
        scene_path: *const c_char,
        options: *const nsf_runtime_options,
        out: *mut *mut nsf_runtime,
    ) -> nsf_status;
    pub fn nsf_runtime_destroy(runtime: *mut nsf_runtime);

    pub fn nsf_runtime_particle_count(runtime: *const nsf_runtime, out: *mut usize) -> nsf_status;
    pub fn nsf_runtime_frame_count(runtime: *const nsf_runtime, out: *mut c_int) -> nsf_status;
    pub fn nsf_runtime_frame_time(runtime: *const nsf_runtime, out: *mut f64) -> nsf_status;
    pub fn nsf_runtime_steps_per_frame(runtime: *const nsf_runtime, out: *mut c_int) -> nsf_status;
    pub fn nsf_runtime_time(runtime: *const nsf_runtime, out: *mut f64) -> nsf_status;

    pub fn nsf_runtime_step(runtime: *mut nsf_runtime) -> nsf_status;
    pub fn nsf_runtime_advance_frame(runtime: *mut nsf_runtime) -> nsf_status;

    pub fn nsf_runtime_positions(
        runtime: *const nsf_runtime,
        out: *mut f32,
        size: usize,
    ) -> nsf_status;
    pub fn nsf_runtime_velocities(
        runtime: *const nsf_runtime,
        out: *mut f32,
        size: usize,
    ) -> nsf_status;
    pub fn nsf_runtime_stress(
        runtime: *const nsf_runtime,
        out: *mut f32,
        size: usize,
    ) -> nsf_status;
    pub fn nsf_runtime_latent_dim(runtime: *const nsf_runtime, out: *mut usize) -> nsf_status;
    pub fn nsf_runtime_latent(
        runtime: *const nsf_runtime,
        out: *mut f32,
        size: usize,
    ) -> nsf_status;

    pub fn nsf_runtime_health(runtime: *const nsf_runtime, out: *mut nsf_health) -> nsf_status;
    pub fn nsf_runtime_last_recovery(
        runtime: *const nsf_runtime,
        out: *mut c_char,
        size: usize,
        length: *mut usize,
    ) -> nsf_status;
    pub fn nsf_runtime_training_note(
        runtime: *const nsf_runtime,
        out: *mut c_char,
        size: usize,
        length: *mut usize,
    ) -> nsf_status;

    pub fn nsf_runtime_collider_count(runtime: *const nsf_runtime, out: *mut usize) -> nsf_status;
    pub fn nsf_runtime_collider_type(
        runtime: *const nsf_runtime,
        index: usize,
        out: *mut c_char,
        size: usize,
        length: *mut usize,
    ) -> nsf_status;
    pub fn nsf_runtime_object_count(runtime: *const nsf_runtime, out: *mut usize) -> nsf_status;
    pub fn nsf_runtime_object_pose(
        runtime: *const nsf_runtime,
        index: usize,
        out: *mut nsf_object_pose,
    ) -> nsf_status;
    pub fn nsf_runtime_collider_pose(
        runtime: *const nsf_runtime,
        index: usize,
        out: *mut nsf_collider_pose,
    ) -> nsf_status;
    pub fn nsf_runtime_set_collider_pose(
        runtime: *mut nsf_runtime,
        index: usize,
        pose: *const nsf_collider_pose,
    ) -> nsf_status;
}
