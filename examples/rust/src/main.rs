//! Embedding nsf from Rust through its C API: what examples/c/main.c does, line for line (the two
//! print the same text). Usage: rust_host MODEL SCENE MU [LIFT].
use nsf::{Options, Runtime};
use std::process::ExitCode;

fn run(model: &str, scene: &str, mu: f64, lift: f64) -> nsf::Result<bool> {
    let (major, minor, patch) = nsf::version_numbers()?;
    println!("nsf {} ({major}.{minor}.{patch})", nsf::version());

    // The error path: a model file that does not exist is an Err with nsf's code and message.
    match Runtime::new("no/such/model.nsf", scene, &Options::default()) {
        Ok(_) => {
            eprintln!("rust_host: a missing model made a runtime");
            return Ok(false);
        }
        Err(e) => println!("missing model: {e}"),
    }

    let options = Options {
        mu: Some(mu),
        threads: 2,
        ..Options::default()
    };
    let mut rom = Runtime::new(model, scene, &options)?;
    let particles = rom.particle_count()?;
    let frames = rom.frame_count()?;
    let latent_dim = rom.latent_dim()?;
    if rom.collider_count()? == 0 {
        eprintln!("rust_host: the scene has no collider to move");
        return Ok(false);
    }
    let mut pose = rom.collider_pose(0)?;
    let y0 = pose.position[1];
    println!(
        "{particles} particles, {frames} frames of {:.4} s, {} steps each, latent of {latent_dim}, collider 0: {}",
        rom.frame_time()?,
        rom.steps_per_frame()?,
        rom.collider_type(0)?
    );

    let mut x = vec![0f32; 3 * particles]; // the host's own buffers
    let mut tau = vec![0f32; 9 * particles];
    let mut z = vec![0f32; latent_dim];
    for frame in 1..=frames {
        pose.position[1] = y0 + lift * rom.time()?; // the host moves collider 0 ...
        pose.velocity[1] = lift; // ... and says how fast it goes
        rom.set_collider_pose(0, &pose)?;
        rom.advance_frame()?;

        rom.positions(&mut x)?;
        let health = rom.health()?;
        let mut c = [0f64; 3];
        for p in x.chunks_exact(3) {
            for k in 0..3 {
                c[k] += f64::from(p[k]);
            }
        }
        let n = particles as f64;
        println!(
            "frame {frame:2}  t {:.4}  centroid {:.6} {:.6} {:.6}  indicator {:.4}  flagged {}  recoveries {}",
            rom.time()?,
            c[0] / n,
            c[1] / n,
            c[2] / n,
            health.indicator,
            health.flagged as i32,
            health.recoveries
        );
    }

    // The stress and the latent at the last frame; a buffer one float short is refused.
    rom.stress(&mut tau)?;
    rom.latent(&mut z)?;
    println!(
        "tau of particle 0: {:.3} {:.3} {:.3} (diagonal, Pa); z0 {:.6}",
        tau[0], tau[4], tau[8], z[0]
    );
    // Object 0 as a rigid body: its centre of mass, velocity and rigid-fit misfit.
    let body = rom.object_pose(0)?;
    println!(
        "object 0: centre {:.6} {:.6} {:.6}  velocity {:.6} {:.6} {:.6}  misfit {:.6} m",
        body.position[0],
        body.position[1],
        body.position[2],
        body.velocity[0],
        body.velocity[1],
        body.velocity[2],
        body.misfit
    );
    let short = x.len() - 1;
    match rom.positions(&mut x[..short]) {
        Err(e) if e.status == nsf::ffi::NSF_ERROR_BUFFER_TOO_SMALL => println!("short buffer: {e}"),
        other => {
            eprintln!("rust_host: a short buffer gave {other:?}");
            return Ok(false);
        }
    }
    Ok(true) // rom is dropped here: nsf_runtime_destroy
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().collect();
    if args.len() < 4 {
        eprintln!("usage: {} MODEL SCENE MU [LIFT]", args[0]);
        return ExitCode::from(2);
    }
    let number = |s: &str| s.parse::<f64>().unwrap_or(0.0);
    let lift = args.get(4).map_or(0.5, |s| number(s));
    match run(&args[1], &args[2], number(&args[3]), lift) {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::FAILURE,
        Err(e) => {
            eprintln!("rust_host: {e}");
            ExitCode::FAILURE
        }
    }
}
