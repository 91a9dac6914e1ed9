// Links libnsf_runtime.so from the nsf install prefix NSF_PREFIX (`cmake --install build --prefix
// P`), with an rpath to it, so that the host runs without LD_LIBRARY_PATH.
use std::env;
use std::path::PathBuf;

fn main() {
    println!("cargo:rerun-if-env-changed=NSF_PREFIX");
    let prefix = match env::var_os("NSF_PREFIX") {
        Some(p) => PathBuf::from(p),
        None => panic!(
            "set NSF_PREFIX to the prefix nsf is installed in (cmake --install build --prefix P)"
        ),
    };
    let lib = ["lib", "lib64"]
        .iter()
        .map(|d| prefix.join(d))
        .find(|d| d.join("libnsf_runtime.so").exists())
        .unwrap_or_else(|| {
            panic!(
                "no lib/libnsf_runtime.so under NSF_PREFIX={}",
                prefix.display()
            )
        });
    println!("cargo:rustc-link-search=native={}", lib.display());
    println!("cargo:rustc-link-lib=dylib=nsf_runtime");
    println!("cargo:rustc-link-arg=-Wl,-rpath,{}", lib.display());
    println!(
        "cargo:rerun-if-changed={}",
        lib.join("libnsf_runtime.so").display()
    );
}
