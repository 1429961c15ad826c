//! What a benchmark report says about the machine and the build it ran on.

use std::process::Command;

/// The CPU's model name from `/proc/cpuinfo` ("unknown" elsewhere).
pub fn cpu_model() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|text| {
            text.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split_once(':'))
                .map(|(_, v)| v.trim().to_string())
        })
        .unwrap_or_else(|| "unknown".into())
}

/// Whether the running CPU has AVX2.
#[cfg(feature = "peers")]
pub fn cpu_has_avx2() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx2")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// Logical cores the process may use.
pub fn cores() -> usize {
    tumble_physics::default_thread_count()
}

/// `git rev-parse --short HEAD` in the current directory, with `-dirty` when the work tree has
/// changes; "unknown" outside a repository.
pub fn git_revision() -> String {
    let run = |args: &[&str]| {
        Command::new("git")
            .args(args)
            .output()
            .ok()
            .filter(|o| o.status.success())
            .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
    };
    match run(&["rev-parse", "--short", "HEAD"]) {
        Some(rev) => {
            let dirty = run(&["status", "--porcelain", "--untracked-files=no"])
                .is_some_and(|s| !s.is_empty());
            if dirty { format!("{rev}-dirty") } else { rev }
        }
        None => "unknown".into(),
    }
}

/// The compiler that built this binary.
pub fn rustc_version() -> &'static str {
    env!("TUMBLE_BENCH_RUSTC")
}

/// `CFLAGS` as the build saw it ("unset" when it was not set).
#[cfg(feature = "peers")]
pub fn build_cflags() -> &'static str {
    env!("TUMBLE_BENCH_CFLAGS")
}

/// Whether this binary was built with optimisations.
pub fn optimised() -> bool {
    !cfg!(debug_assertions)
}
