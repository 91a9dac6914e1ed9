//! A safe wrapper of nsf's C API (include/nsf/nsf.h): `Runtime` owns an `nsf_runtime*` and frees
//! it on drop; every call returns `Result<_, Error>`, the error carrying nsf's code and message.
pub mod ffi;

use std::ffi::{CStr, CString};
use std::fmt;
use std::os::raw::{c_char, c_int};
use std::ptr::{self, NonNull};

/// A failed call: nsf's status code, its name and the message nsf_last_error() gave.
#[derive(Clone, Debug)]
pub struct Error {
    pub status: ffi::nsf_status,
    pub name: String,
    pub message: String,
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}, {}", self.name, self.message)
    }
}

impl std::error::Error for Error {}

pub type Result<T> = std::result::Result<T, Error>;

fn text(p: *const c_char) -> String {
    if p.is_null() {
        return String::new();
    }
    // SAFETY: nsf returns NUL-terminated strings that live until the thread's next nsf call.
    unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned()
}

/// Ok, or the error of the call that just returned `status` (read on the same thread, before any
/// other nsf call, as nsf_last_error asks).
fn check(status: ffi::nsf_status) -> Result<()> {
    if status == ffi::NSF_OK {
        return Ok(());
    }
    // SAFETY: both take no pointer and return static or thread-local strings.
    let (name, message) = unsafe { (ffi::nsf_status_name(status), ffi::nsf_last_error()) };
    Err(Error {
        status,
        name: text(name),
        message: text(message),
    })
}

fn c_string(s: &str, what: &str) -> Result<CString> {
    CString::new(s).map_err(|_| Error {
        status: ffi::NSF_ERROR_INVALID_ARGUMENT,
        name: "NSF_ERROR_INVALID_ARGUMENT".into(),
        message: format!("{what} holds a NUL byte"),
    })
}

/// The library's version, "MAJOR.MINOR.PATCH", and its numbers.
pub fn version() -> String {
    // SAFETY: a static string.
    text(unsafe { ffi::nsf_version() })
}
pub fn version_numbers() -> Result<(i32, i32, i32)> {
    let (mut major, mut minor, mut patch) = (0 as c_int, 0 as c_int, 0 as c_int);
    // SAFETY: three valid out pointers.
    check(unsafe { ffi::nsf_version_numbers(&mut major, &mut minor, &mut patch) })?;
    Ok((major, minor, patch))
}

/// nsf::RuntimeOptions; `Options::default()` holds nsf's defaults.
#[derive(Clone, Debug)]
pub struct Options {
    pub mu: Option<f64>,
    pub samples: i32,
    pub threads: i32,
    pub overrides: Vec<String>,
    pub indicator_misfit_cells: f64,
    pub indicator_courant: f64,
    pub indicator_grid_margin: f64,
    pub recover: bool,
}

impl Default for Options {
    fn default() -> Self {
        let mut o = std::mem::MaybeUninit::<ffi::nsf_runtime_options>::uninit();
        // SAFETY: options_init writes every field of a valid pointer; it cannot fail then.
        let o = unsafe {
            ffi::nsf_runtime_options_init(o.as_mut_ptr());
            o.assume_init()
        };
        Options {
            mu: None,
            samples: o.samples,
            threads: o.threads,
            overrides: Vec::new(),
            indicator_misfit_cells: o.indicator_misfit_cells,
            indicator_courant: o.indicator_courant,
            indicator_grid_margin: o.indicator_grid_margin,
            recover: o.recover != 0,
        }
    }
}

/// RuntimeHealth, with the texts of the last recovery and of the first step outside the
/// model's training box.
#[derive(Clone, Debug, Default)]
pub struct Health {
    pub indicator: f64,
    pub misfit_cells: f64,
    pub courant: f64,
    pub grid_margin: f64,
    pub flagged: bool,
    pub recoveries: i64,
    pub last_recovery: String,
    pub outside_training: bool,
    pub steps_outside: i64,
    pub training_note: String,
}

pub type ColliderPose = ffi::nsf_collider_pose;
/// A scene object as a rigid body fitted to its particles (nsf::ObjectPose).
pub type ObjectPose = ffi::nsf_object_pose;

/// The reduced-order simulator of one scene at one μ; freed on drop. Not Send: use it on the
/// thread that made it.
pub struct Runtime {
    handle: NonNull<ffi::nsf_runtime>,
}

impl Drop for Runtime {
    fn drop(&mut self) {
        // SAFETY: the handle came from nsf_runtime_create and is freed once.
        unsafe { ffi::nsf_runtime_destroy(self.handle.as_ptr()) }
    }
}

/// A getter of one value through an out pointer.
macro_rules! getter {
    ($name:ident, $f:ident, $t:ty) => {
        pub fn $name(&self) -> Result<$t> {
            let mut out: $t = Default::default();
            // SAFETY: a live handle and a valid out pointer.
            check(unsafe { ffi::$f(self.handle.as_ptr(), &mut out) })?;
            Ok(out)
        }
    };
}

/// A reader of floats into the caller's slice.
macro_rules! reader {
    ($name:ident, $f:ident) => {
        pub fn $name(&self, out: &mut [f32]) -> Result<()> {
            // SAFETY: a live handle; nsf writes at most out.len() floats.
            check(unsafe { ffi::$f(self.handle.as_ptr(), out.as_mut_ptr(), out.len()) })
        }
    };
}

impl Runtime {
    /// Loads the model and its scene (nsf_runtime_create).
    pub fn new(model: &str, scene: &str, options: &Options) -> Result<Runtime> {
        let model = c_string(model, "the model path")?;
        let scene = c_string(scene, "the scene path")?;
        let overrides = options
            .overrides
            .iter()
            .map(|s| c_string(s, "an override"))
            .collect::<Result<Vec<_>>>()?;
        let pointers: Vec<*const c_char> = overrides.iter().map(|s| s.as_ptr()).collect();
        let o = ffi::nsf_runtime_options {
            has_mu: options.mu.is_some() as c_int,
            mu: options.mu.unwrap_or(0.0),
            samples: options.samples,
            threads: options.threads,
            overrides: if pointers.is_empty() {
                ptr::null()
            } else {
                pointers.as_ptr()
            },
            override_count: pointers.len(),
            indicator_misfit_cells: options.indicator_misfit_cells,
            indicator_courant: options.indicator_courant,
            indicator_grid_margin: options.indicator_grid_margin,
            recover: options.recover as c_int,
        };
        let mut handle = ptr::null_mut();
        // SAFETY: NUL-terminated paths and overrides that outlive the call; a valid out pointer.
        check(unsafe { ffi::nsf_runtime_create(model.as_ptr(), scene.as_ptr(), &o, &mut handle) })?;
        let handle = NonNull::new(handle).expect("nsf_runtime_create returned NSF_OK and NULL");
        Ok(Runtime { handle })
    }

    getter!(particle_count, nsf_runtime_particle_count, usize);
    getter!(frame_count, nsf_runtime_frame_count, c_int);
    getter!(frame_time, nsf_runtime_frame_time, f64);
    getter!(steps_per_frame, nsf_runtime_steps_per_frame, c_int);
    getter!(time, nsf_runtime_time, f64);
    getter!(latent_dim, nsf_runtime_latent_dim, usize);
    getter!(collider_count, nsf_runtime_collider_count, usize);

    pub fn step(&mut self) -> Result<()> {
        // SAFETY: a live handle.
        check(unsafe { ffi::nsf_runtime_step(self.handle.as_ptr()) })
    }
    pub fn advance_frame(&mut self) -> Result<()> {
        // SAFETY: a live handle.
        check(unsafe { ffi::nsf_runtime_advance_frame(self.handle.as_ptr()) })
    }

    // x, v (3 floats per particle), τ (9, row-major) and the latent into the caller's slice.
    reader!(positions, nsf_runtime_positions);
    reader!(velocities, nsf_runtime_velocities);
    reader!(stress, nsf_runtime_stress);
    reader!(latent, nsf_runtime_latent);

    pub fn health(&self) -> Result<Health> {
        let mut h = ffi::nsf_health::default();
        // SAFETY: a live handle and a valid out pointer.
        check(unsafe { ffi::nsf_runtime_health(self.handle.as_ptr(), &mut h) })?;
        let handle = self.handle.as_ptr();
        let last_recovery = read_text(|out, size, length| unsafe {
            // SAFETY: a live handle; out holds size bytes (or is NULL with size 0).
            ffi::nsf_runtime_last_recovery(handle, out, size, length)
        })?;
        let training_note = read_text(|out, size, length| unsafe {
            // SAFETY: a live handle; out holds size bytes (or is NULL with size 0).
            ffi::nsf_runtime_training_note(handle, out, size, length)
        })?;
        Ok(Health {
            indicator: h.indicator,
            misfit_cells: h.misfit_cells,
            courant: h.courant,
            grid_margin: h.grid_margin,
            flagged: h.flagged != 0,
            recoveries: h.recoveries,
            last_recovery,
            outside_training: h.outside_training != 0,
            steps_outside: h.steps_outside,
            training_note,
        })
    }

    pub fn collider_type(&self, index: usize) -> Result<String> {
        let handle = self.handle.as_ptr();
        read_text(|out, size, length| unsafe {
            // SAFETY: a live handle; out holds size bytes (or is NULL with size 0).
            ffi::nsf_runtime_collider_type(handle, index, out, size, length)
        })
    }
    pub fn object_count(&self) -> Result<usize> {
        let mut n = 0usize;
        // SAFETY: a live handle and a valid out pointer.
        check(unsafe { ffi::nsf_runtime_object_count(self.handle.as_ptr(), &mut n) })?;
        Ok(n)
    }
    pub fn object_pose(&self, index: usize) -> Result<ObjectPose> {
        let mut pose = ObjectPose::default();
        // SAFETY: a live handle and a valid out pointer.
        check(unsafe { ffi::nsf_runtime_object_pose(self.handle.as_ptr(), index, &mut pose) })?;
        Ok(pose)
    }
    pub fn collider_pose(&self, index: usize) -> Result<ColliderPose> {
        let mut pose = ColliderPose::default();
        // SAFETY: a live handle and a valid out pointer.
        check(unsafe { ffi::nsf_runtime_collider_pose(self.handle.as_ptr(), index, &mut pose) })?;
        Ok(pose)
    }
    pub fn set_collider_pose(&mut self, index: usize, pose: &ColliderPose) -> Result<()> {
        // SAFETY: a live handle and a valid pose.
        check(unsafe { ffi::nsf_runtime_set_collider_pose(self.handle.as_ptr(), index, pose) })
    }
}

/// A text of the C API: its length first (a NULL buffer of size 0), then the text.
fn read_text(f: impl Fn(*mut c_char, usize, *mut usize) -> ffi::nsf_status) -> Result<String> {
    let mut length = 0usize;
    check(f(ptr::null_mut(), 0, &mut length))?;
    let mut buf = vec![0 as c_char; length + 1];
    check(f(buf.as_mut_ptr(), buf.len(), &mut length))?;
    Ok(text(buf.as_ptr()))
}
