//! `cargo xtask fuzz`: runs the scene loader's fuzz target (`fuzz/`, cargo-fuzz and libFuzzer
//! on nightly) for a bounded time, keeps what it finds in the corpus in the repo, minimises
//! the corpus, and says how many inputs ran. Not part of `test`: it needs minutes of CPU. The
//! corpus it leaves is replayed by `tests/tests/fuzz_corpus.rs` in every `cargo xtask test`.

use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::{Command, Stdio};

use crate::{cargo, run_status, succeeds, web};

pub const USAGE: &str =
    "  fuzz    run the scene loader's fuzz target (cargo-fuzz, nightly) for a bounded
          time, keep new inputs in fuzz/corpus/scene and minimise it (installs
          nightly and cargo-fuzz when missing)
            --seconds N   how long libFuzzer runs (default 300)";

const TARGET: &str = "scene";
const CORPUS: &str = "fuzz/corpus/scene";

/// `cargo xtask fuzz [--seconds N]`.
pub fn task(root: &Path, args: &[String]) -> Result<(), String> {
    let mut seconds: u64 = 300;
    let mut rest = args.iter();
    while let Some(arg) = rest.next() {
        match arg.as_str() {
            "--seconds" => {
                let value = rest.next().ok_or("--seconds needs a value")?;
                seconds = value
                    .parse()
                    .ok()
                    .filter(|&s| s > 0)
                    .ok_or_else(|| format!("--seconds {value}: not a whole number > 0"))?;
            }
            other => return Err(format!("unknown argument `{other}`")),
        }
    }
    web::ensure_nightly_toolchain()?;
    ensure_cargo_fuzz()?;
    let corpus = root.join(CORPUS);
    std::fs::create_dir_all(&corpus)
        .map_err(|e| format!("cannot create {}: {e}", corpus.display()))?;
    let before = count_files(&corpus);
    println!("fuzzing `{TARGET}` for {seconds} s from {before} corpus inputs");

    let mut run = nightly_fuzz(root);
    run.args(["run", TARGET, CORPUS, "--", "-rss_limit_mb=4096"])
        .arg(format!("-max_total_time={seconds}"))
        .stderr(Stdio::piped());
    let mut child = run
        .spawn()
        .map_err(|e| format!("cannot run `cargo +nightly fuzz run`: {e}"))?;
    // libFuzzer reports on stderr; echo it and keep its closing "Done N runs" line.
    let mut done = None;
    if let Some(stderr) = child.stderr.take() {
        for line in BufReader::new(stderr).lines().map_while(Result::ok) {
            eprintln!("{line}");
            if line.starts_with("Done ") {
                done = Some(line);
            }
        }
    }
    let status = child
        .wait()
        .map_err(|e| format!("cargo fuzz run did not finish: {e}"))?;
    if !status.success() {
        return Err(format!(
            "the fuzzer found a failing input ({status}); it is in fuzz/artifacts/{TARGET}/: \
             replay it with `cargo +nightly fuzz run {TARGET} fuzz/artifacts/{TARGET}/<file>`, \
             fix the loader, and add the file to {CORPUS}"
        ));
    }
    let grown = count_files(&corpus);
    run_status(
        nightly_fuzz(root).args(["cmin", TARGET, CORPUS]),
        "cargo +nightly fuzz cmin scene",
    )?;
    let after = count_files(&corpus);
    println!(
        "fuzz: {}; no crash; corpus {before} -> {grown} inputs, {after} after minimising \
         (commit {CORPUS})",
        done.as_deref().unwrap_or("the run count was not reported")
    );
    Ok(())
}

/// `cargo +nightly fuzz` from the workspace root, under nightly whatever runs xtask.
fn nightly_fuzz(root: &Path) -> Command {
    let mut cmd = Command::new("cargo");
    cmd.args(["+nightly", "fuzz"])
        .current_dir(root)
        .env_remove("RUSTUP_TOOLCHAIN")
        .env_remove("RUSTC")
        .env_remove("RUSTDOC");
    cmd
}

/// cargo-fuzz from crates.io when `cargo fuzz` is missing.
fn ensure_cargo_fuzz() -> Result<(), String> {
    if succeeds(Command::new(cargo()).args(["fuzz", "--version"])) {
        return Ok(());
    }
    println!("cargo-fuzz is missing; installing it (about 2 minutes)");
    run_status(
        Command::new(cargo()).args(["install", "cargo-fuzz", "--locked", "-j2"]),
        "cargo install cargo-fuzz --locked",
    )
}

fn count_files(dir: &Path) -> usize {
    std::fs::read_dir(dir).map_or(0, |entries| {
        entries
            .filter_map(Result::ok)
            .filter(|e| e.path().is_file())
            .count()
    })
}
