//! What a benchmark report says about the machine and the build it ran on.

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

/// The first three fields of `/proc/loadavg` ("unknown" elsewhere): how busy the machine was.
pub fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .ok()
        .map(|t| t.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|| "unknown".into())
}

/// Logical cores the process may use.
pub fn cores() -> usize {
    tumble_physics::default_thread_count()
}

/// The revision of the source this binary was built from (`git rev-parse --short HEAD` at
/// build time, `-dirty` when tracked files differed from it); "unknown" outside a repository.
pub fn git_revision() -> &'static str {
    env!("TUMBLE_BENCH_GIT_REVISION")
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

/// The kernels tumble's solver runs its 8-lane colours with on this CPU (`avx2`, chosen at
/// run time, or `portable`), as a table cell.
pub fn tumble_kernel() -> String {
    let world = tumble_physics::World::new(tumble_physics::StepSettings::default());
    match world.simd_kernel() {
        "avx2" => "AVX2, 256-bit (detected at run time; the build itself is portable)".into(),
        other => format!("{other} (no AVX2 on this CPU)"),
    }
}

/// Starts a report's machine table: its header, then the CPU, the cores and the revision.
pub fn write_host_rows(md: &mut String) {
    use std::fmt::Write as _;
    let _ = writeln!(md, "| | |\n|---|---|");
    let _ = writeln!(md, "| CPU | {} |", cpu_model());
    let _ = writeln!(md, "| cores | {} |", cores());
    let _ = writeln!(
        md,
        "| tumble revision (built from) | `{}` |",
        git_revision()
    );
}

/// The machine table's build row: release, or a debug build whose timings mean nothing.
pub fn write_build_row(md: &mut String) {
    use std::fmt::Write as _;
    let build = if optimised() {
        "release"
    } else {
        "debug (timings meaningless)"
    };
    let _ = writeln!(md, "| build | {build} |");
}
