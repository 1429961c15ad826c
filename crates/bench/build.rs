//! Records, for the reports of `tumble-bench sweep` and `compare`, what only the build knows:
//! the revision of the source it was built from, the compiler's version, the C flags that cargo's environment passed to dependencies' C builds (boxdd's
//! Box2D build reads `CFLAGS` through the `cc` crate), and the peer crates' locked versions.

use std::path::Path;
use std::process::Command;

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-env-changed=CFLAGS");
    println!("cargo:rerun-if-env-changed=TARGET_CFLAGS");

    let rustc = std::env::var("RUSTC").unwrap_or_else(|_| "rustc".into());
    let version = Command::new(&rustc)
        .arg("--version")
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        .unwrap_or_else(|| "unknown".into());
    println!("cargo:rustc-env=TUMBLE_BENCH_RUSTC={version}");

    // `CFLAGS` as cc sees it for the target ("unset" when absent), one line.
    let cflags = std::env::var("CFLAGS")
        .or_else(|_| std::env::var("TARGET_CFLAGS"))
        .map(|s| s.replace(['\n', '\r'], " "))
        .unwrap_or_else(|_| "unset".into());
    println!("cargo:rustc-env=TUMBLE_BENCH_CFLAGS={cflags}");

    git_revision();

    // The workspace's lock file, two levels up from this crate.
    let manifest = std::env::var("CARGO_MANIFEST_DIR").unwrap_or_default();
    let lock = Path::new(&manifest).join("../../Cargo.lock");
    println!("cargo:rerun-if-changed={}", lock.display());
    let text = std::fs::read_to_string(&lock).unwrap_or_default();
    for (krate, key) in [("boxdd", "BOXDD"), ("rapier2d", "RAPIER2D")] {
        println!(
            "cargo:rustc-env=TUMBLE_BENCH_{key}_VERSION={}",
            locked_version(&text, krate).unwrap_or_else(|| "unknown".into())
        );
    }
}

/// The version of `krate` in a Cargo.lock (the first entry of that name).
fn locked_version(lock: &str, krate: &str) -> Option<String> {
    let mut lines = lock.lines();
    while let Some(line) = lines.next() {
        if line.trim() == format!("name = \"{krate}\"") {
            let next = lines.next()?.trim();
            return next
                .strip_prefix("version = \"")
                .and_then(|v| v.strip_suffix('"'))
                .map(str::to_string);
        }
    }
    None
}

/// `git rev-parse --short HEAD` of the source being built, `-dirty` when tracked files differ
/// from it. Read-only: `--no-optional-locks` keeps `git status` from refreshing the index.
fn git_revision() {
    let git = |args: &[&str]| {
        Command::new("git")
            .arg("--no-optional-locks")
            .args(args)
            .output()
            .ok()
            .filter(|o| o.status.success())
            .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
    };
    let revision = match git(&["rev-parse", "--short", "HEAD"]) {
        Some(rev) => {
            let dirty = git(&["status", "--porcelain", "--untracked-files=no"])
                .is_some_and(|s| !s.is_empty());
            if dirty { format!("{rev}-dirty") } else { rev }
        }
        None => "unknown".into(),
    };
    println!("cargo:rustc-env=TUMBLE_BENCH_GIT_REVISION={revision}");
    // Rebuild the note when HEAD moves or the engine's source changes.
    if let Some(dir) = git(&["rev-parse", "--absolute-git-dir"]) {
        for path in ["HEAD", "refs/heads", "packed-refs"] {
            let p = Path::new(&dir).join(path);
            if p.exists() {
                println!("cargo:rerun-if-changed={}", p.display());
            }
        }
    }
    let manifest = std::env::var("CARGO_MANIFEST_DIR").unwrap_or_default();
    for dir in ["src", "../physics/src", "../scene/src"] {
        println!(
            "cargo:rerun-if-changed={}",
            Path::new(&manifest).join(dir).display()
        );
    }
}
