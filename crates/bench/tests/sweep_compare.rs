//! `tumble-bench sweep` and `tumble-bench compare` on tiny configurations: the files they write
//! exist and parse.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::atomic::{AtomicUsize, Ordering};

const BIN: &str = env!("CARGO_BIN_EXE_tumble-bench");

fn bench(args: &[&str]) -> Output {
    Command::new(BIN)
        .args(args)
        .output()
        .expect("the tumble-bench binary runs")
}

#[track_caller]
fn succeeded(out: &Output) -> String {
    assert!(
        out.status.success(),
        "exit {:?}\nstdout:\n{}\nstderr:\n{}",
        out.status,
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// A fresh directory under the temp dir, removed when dropped.
struct TempDir(PathBuf);

impl TempDir {
    fn new(name: &str) -> TempDir {
        static COUNTER: AtomicUsize = AtomicUsize::new(0);
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        let path =
            std::env::temp_dir().join(format!("tumble-bench-{name}-{}-{n}", std::process::id()));
        let _ = std::fs::remove_dir_all(&path);
        TempDir(path)
    }

    fn path(&self) -> &str {
        self.0.to_str().expect("temp paths are UTF-8 here")
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Reads a CSV: its header's fields and its rows' fields, every row as wide as the header.
#[track_caller]
fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path)
        .unwrap_or_else(|e| panic!("{} is readable: {e}", path.display()));
    let mut lines = text.lines();
    let header: Vec<String> = lines
        .next()
        .expect("a header line")
        .split(',')
        .map(str::to_string)
        .collect();
    let rows: Vec<Vec<String>> = lines
        .filter(|l| !l.is_empty())
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    for row in &rows {
        assert_eq!(row.len(), header.len(), "{}: {row:?}", path.display());
    }
    (header, rows)
}

fn column(header: &[String], name: &str) -> usize {
    header
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("no column {name} in {header:?}"))
}

#[track_caller]
fn number(text: &str) -> f64 {
    let x: f64 = text
        .parse()
        .unwrap_or_else(|_| panic!("{text:?} is not a number"));
    assert!(x.is_finite() && x >= 0.0, "{text}");
    x
}

#[track_caller]
fn check_svg(path: &Path) {
    let text = std::fs::read_to_string(path)
        .unwrap_or_else(|e| panic!("{} is readable: {e}", path.display()));
    assert!(
        text.starts_with("<svg"),
        "{} starts with {:?}",
        path.display(),
        &text[..20]
    );
    assert!(
        text.trim_end().ends_with("</svg>"),
        "{} is complete",
        path.display()
    );
    assert!(text.contains("<text"), "{} has labels", path.display());
    assert!(text.contains("<polyline"), "{} has lines", path.display());
}

#[test]
fn a_tiny_sweep_writes_a_csv_and_charts() {
    let dir = TempDir::new("sweep");
    let out = bench(&[
        "sweep",
        "--scenes",
        "pyramid",
        "--threads",
        "1",
        "--repeats",
        "1",
        "--steps",
        "3",
        "--warmup",
        "2",
        "--bodies",
        "100",
        "--out-dir",
        dir.path(),
    ]);
    let stdout = succeeded(&out);
    assert!(
        stdout.contains("pyramid"),
        "the table names the scene:\n{stdout}"
    );
    assert!(
        stdout.contains("pile_100"),
        "the table names the pile:\n{stdout}"
    );

    let (header, rows) = read_csv(&dir.0.join("sweep.csv"));
    for name in [
        "family",
        "scene",
        "bodies",
        "threads",
        "repeat",
        "step_ms",
        "solve_ms",
        "broad_phase_ms",
    ] {
        column(&header, name);
    }
    // The pile runs in every engine built in (tumble first in the first repeat).
    let engines: &[&str] = if cfg!(feature = "peers") {
        &["tumble", "box2d", "rapier"]
    } else {
        &["tumble"]
    };
    assert_eq!(
        rows.len(),
        1 + engines.len(),
        "one pyramid run and one pile run per engine: {rows:?}"
    );
    let (scene, family) = (column(&header, "scene"), column(&header, "family"));
    let engine = column(&header, "engine");
    assert_eq!(rows[0][scene], "pyramid");
    assert_eq!(rows[0][family], "threads");
    assert_eq!(rows[0][engine], "tumble");
    for (row, name) in rows[1..].iter().zip(engines) {
        assert_eq!(row[scene], "pile_100");
        assert_eq!(row[family], "bodies");
        assert_eq!(row[engine], *name);
        assert_eq!(number(&row[column(&header, "bodies")]), 103.0);
    }
    for row in &rows {
        number(&row[column(&header, "step_ms")]);
        if row[engine] == "tumble" {
            number(&row[column(&header, "solve_ms")]);
        }
    }
    if !cfg!(feature = "peers") {
        assert!(
            stdout.contains("tumble only"),
            "a sweep without peers says so:\n{stdout}"
        );
    }

    check_svg(&dir.0.join("sweep_threads_pyramid.svg"));
    check_svg(&dir.0.join("sweep_bodies.svg"));
    let md = std::fs::read_to_string(dir.0.join("sweep.md")).expect("sweep.md");
    assert!(md.contains("sweep_bodies.svg"));
}

#[test]
fn a_sweep_refuses_bad_lists() {
    for args in [
        &["sweep", "--threads", "0"][..],
        &["sweep", "--bodies", "10,x"][..],
        &["sweep", "--scenes", "no_such_scene", "--bodies", "none"][..],
    ] {
        let out = bench(args);
        assert!(!out.status.success(), "{args:?} should fail");
        assert!(out.status.code().is_some());
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!stderr.contains("panicked"), "{stderr}");
    }
}

#[cfg(not(feature = "peers"))]
#[test]
fn compare_without_peers_says_how_to_rebuild() {
    let out = bench(&["compare", "--scenes", "pyramid"]);
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("--features peers"), "{stderr}");
}

#[cfg(feature = "peers")]
#[test]
fn a_tiny_compare_writes_its_report() {
    let dir = TempDir::new("compare");
    let out = bench(&[
        "compare",
        "--scenes",
        "pyramid",
        "--threads",
        "1",
        "--repeats",
        "2",
        "--warmup",
        "3",
        "--steps",
        "5",
        "--check-steps",
        "120",
        "--out-dir",
        dir.path(),
    ]);
    let stdout = succeeded(&out);
    assert!(stdout.contains("cross-check"), "{stdout}");

    let (header, rows) = read_csv(&dir.0.join("compare.csv"));
    assert_eq!(rows.len(), 1, "{rows:?}");
    assert_eq!(rows[0][column(&header, "scene")], "pyramid");
    for name in [
        "tumble_median_ms",
        "box2d_median_ms",
        "rapier_median_ms",
        "tumble_over_box2d",
        "tumble_over_rapier",
    ] {
        assert!(number(&rows[0][column(&header, name)]) > 0.0, "{name}");
    }
    // Each ratio is the median of the runs' ratios, within their spread.
    for peer in ["box2d", "rapier"] {
        let at = |name: &str| number(&rows[0][column(&header, name)]);
        let (least, median, most) = (
            at(&format!("tumble_over_{peer}_least")),
            at(&format!("tumble_over_{peer}")),
            at(&format!("tumble_over_{peer}_most")),
        );
        assert!(
            least <= median && median <= most,
            "{peer}: {least} {median} {most}"
        );
    }
    let (runs_header, runs) = read_csv(&dir.0.join("compare_runs.csv"));
    assert_eq!(runs.len(), 6, "one run per engine and repeat: {runs:?}");
    // In the order they ran: the engines' order rotates, so the second repeat starts with
    // Box2D, not tumble.
    let engine = column(&runs_header, "engine");
    let first_of = |repeat: &str| {
        runs.iter()
            .find(|r| r[column(&runs_header, "repeat")] == repeat)
            .map(|r| r[engine].clone())
    };
    assert_eq!(first_of("1").as_deref(), Some("tumble"), "{runs:?}");
    assert_eq!(first_of("2").as_deref(), Some("box2d"), "{runs:?}");

    let md = std::fs::read_to_string(dir.0.join("compare.md")).expect("compare.md");
    for word in [
        "Box2D",
        "Rapier",
        "CPU",
        "rustc",
        "Cross-check",
        "| pyramid |",
        "steps 3 times untimed",
        "rotates",
    ] {
        assert!(md.contains(word), "compare.md lacks {word:?}:\n{md}");
    }

    // The three engines agree on where the top box of the pyramid is after 2 s: still on top.
    let heights: Vec<f64> = stdout
        .lines()
        .skip_while(|l| !l.starts_with("cross-check"))
        .skip(1)
        .take(3)
        .map(|l| {
            let y = l.split_whitespace().skip_while(|w| *w != "y").nth(1);
            number(y.unwrap_or_else(|| panic!("no y in {l:?}")))
        })
        .collect();
    assert_eq!(heights.len(), 3, "{stdout}");
    for y in heights {
        assert!((y - 19.5).abs() < 0.1, "top box at y {y}:\n{stdout}");
    }
}
