//! The package's examples as programs a test runs (e.g. `denoise_box`, the user's denoiser of
//! `denoise_command`'s tests). Cargo gives integration tests the path of the package's binaries
//! (`CARGO_BIN_EXE_*`) but not of its examples, and `cargo test --test NAME` does not build them,
//! so `example` builds the one asked for with the cargo running the tests, into the same target
//! directory and profile as this test binary (found from its own path, target/PROFILE/deps/), and
//! returns target/PROFILE/examples/NAME. Under a plain `cargo test` the examples are already built
//! and the build is a no-op.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Mutex;

pub fn example(name: &str) -> PathBuf {
    // One build at a time: tests of one binary run in parallel and may ask for the same example.
    static BUILD: Mutex<()> = Mutex::new(());
    let _guard = BUILD.lock().unwrap_or_else(|e| e.into_inner());
    let exe = std::env::current_exe().expect("the test binary's path");
    let profile_dir = exe.parent().and_then(Path::parent).expect("target/PROFILE/deps/TEST");
    let target_dir = profile_dir.parent().expect("target/PROFILE");
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| env!("CARGO").into());
    let mut build = Command::new(cargo);
    build.current_dir(env!("CARGO_MANIFEST_DIR")).args(["build", "--quiet", "--locked", "--example", name]);
    build.arg("--target-dir").arg(target_dir);
    if profile_dir.file_name().is_some_and(|p| p == "release") {
        build.arg("--release");
    }
    let status = build.status().expect("run cargo");
    assert!(status.success(), "cargo build --example {name} failed ({status})");
    let path = profile_dir.join("examples").join(format!("{name}{}", std::env::consts::EXE_SUFFIX));
    assert!(path.is_file(), "no example binary at {}", path.display());
    path
}
