//! Building the native side for the tests that run programs against the
//! library (tests/native.rs, tests/mpi.rs, tests/mpi_tube_search.rs): the
//! cdylib and staticlib with this test build's profile and features (so
//! `make test`'s sundials build is not rebuilt in between), then Makefile
//! targets.

#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

pub const ROOT: &str = env!("CARGO_MANIFEST_DIR");

pub fn profile() -> &'static str {
    if cfg!(debug_assertions) {
        "debug"
    } else {
        "release"
    }
}

/// target/<profile>/native, where the Makefile puts the programs.
pub fn build_dir() -> PathBuf {
    Path::new(ROOT).join("target").join(profile()).join("native")
}

/// stdout of a finished command, or a panic with both streams.
pub fn check(out: Output, what: &str) -> String {
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "{what} failed ({}):\n{stdout}\n{}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    stdout
}

/// `cargo test` builds only the rlib: build the library with the same
/// profile and features (a no-op when current), then `make <targets>`.
pub fn build_lib_and_make(targets: &[&str]) {
    cargo_then_make(targets, None);
}

/// `cargo build --lib` with this build's profile and features, then `make
/// <targets>`; with `target`, both in that target directory (the Makefile
/// gets it as TARGET_DIR).
fn cargo_then_make(targets: &[&str], target: Option<&Path>) {
    let mut cargo = Command::new(env!("CARGO"));
    cargo.current_dir(ROOT).args(["build", "--lib", "--quiet"]);
    if let Some(t) = target {
        cargo.env("CARGO_TARGET_DIR", t);
    }
    if profile() == "release" {
        cargo.arg("--release");
    }
    if cfg!(feature = "sundials") {
        cargo.args(["--features", "sundials"]);
    }
    check(cargo.output().expect("run cargo build"), "cargo build --lib");
    let mut make = Command::new("make");
    make.current_dir(ROOT).args(["--no-print-directory", "-s", &format!("PROFILE={}", profile())]);
    if let Some(t) = target {
        make.arg(format!("TARGET_DIR={}", t.display()));
    }
    check(make.args(targets).output().expect("run make"), &format!("make {}", targets.join(" ")));
}

/// The target directory of this test build (CARGO_TARGET_DIR when set,
/// else the repository's target/): the test executable lives in
/// <target>/<profile>/deps.
pub fn test_target_dir() -> PathBuf {
    let exe = std::env::current_exe().unwrap();
    exe.parent().and_then(Path::parent).and_then(Path::parent).unwrap().to_path_buf()
}

/// The library (cargo, this build's profile and features), then `make
/// <targets>`, both in this test build's target directory (the Makefile
/// gets it as TARGET_DIR, so a build in another target directory neither
/// uses nor overwrites target/). Returns <target>/<profile>/native, where
/// the Makefile puts the programs.
pub fn build_in_test_target(targets: &[&str]) -> PathBuf {
    let target = test_target_dir();
    cargo_then_make(targets, Some(&target));
    target.join(profile()).join("native")
}
