//! `tumble-bench report --quick`: the files it writes exist and parse, and every case has its
//! table, its chart and its summary row; with `--features peers`, Box2D's and Rapier's rows too.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const BIN: &str = env!("CARGO_BIN_EXE_tumble-bench");

/// The cases of the report, by chart name.
const CASES: [&str; 14] = [
    "vertical_stack",
    "pyramid",
    "large_pyramid",
    "pyramid_200",
    "mass_ratio_10",
    "mass_ratio_100",
    "mass_ratio_1000",
    "friction_incline",
    "restitution_drop",
    "projectile",
    "elastic_box",
    "elastic_box_gravity",
    "overlap_recovery",
    "far_from_origin",
];

/// A fresh directory under the temp dir, removed when dropped.
struct TempDir(PathBuf);

impl TempDir {
    fn new(name: &str) -> TempDir {
        let path = std::env::temp_dir().join(format!("tumble-bench-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&path);
        TempDir(path)
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

fn bench(args: &[&str]) -> Output {
    Command::new(BIN)
        .args(args)
        .output()
        .expect("the tumble-bench binary runs")
}

#[track_caller]
fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{} is readable: {e}", path.display()))
}

/// An SVG that is whole: opens and closes, has its axis labels, and every text element that
/// opens closes (a cheap well-formedness check). Its points may be missing: a case whose
/// metric needs more than the quick run's 10 steps (a bounce) has none.
#[track_caller]
fn check_svg(path: &Path) {
    let text = read(path);
    assert!(text.starts_with("<svg"), "{} is not an SVG", path.display());
    assert!(
        text.trim_end().ends_with("</svg>"),
        "{} is cut short",
        path.display()
    );
    for needle in ["<text", "ms per step"] {
        assert!(text.contains(needle), "{} lacks {needle}", path.display());
    }
    let opens = text.matches("<text").count();
    let closes = text.matches("</text>").count();
    assert_eq!(opens, closes, "{}: unbalanced <text>", path.display());
}

#[test]
fn a_quick_report_writes_markdown_csv_and_a_chart_per_case() {
    let dir = TempDir::new("report");
    let out = bench(&["report", "--quick", "--out-dir", dir.0.to_str().unwrap()]);
    assert!(
        out.status.success(),
        "exit {:?}\nstderr:\n{}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    for case in CASES {
        check_svg(&dir.0.join(format!("{case}.svg")));
    }
    // A stack's metrics exist after 10 steps: its chart has points and fronts.
    let stack = read(&dir.0.join("vertical_stack.svg"));
    assert!(stack.contains("<circle") && stack.contains("<polyline"));

    let md = read(&dir.0.join("REPORT.md"));
    for needle in [
        "# Speed against error",
        "| CPU |",
        "| tumble revision (built from) |",
        "| rustc |",
        "| load average (1, 5, 15 min) |",
        "Quick run",
        "## Summary: the cheapest setting that passes",
        "## Not measured: orbit-like motion",
    ] {
        assert!(md.contains(needle), "REPORT.md lacks {needle:?}");
    }
    for case in CASES {
        assert!(
            md.contains(&format!("]({case}.svg)")),
            "REPORT.md does not link {case}.svg"
        );
    }
    // Every table row has as many cells as its header.
    let mut header_cells = 0;
    for line in md.lines().filter(|l| l.starts_with('|')) {
        let cells = line.matches('|').count();
        if line.starts_with("|---") || line.starts_with("|--") {
            continue;
        }
        if line.starts_with("| engine |") || line.starts_with("| case |") || line == "| | |" {
            header_cells = cells;
        } else if header_cells > 0 {
            assert_eq!(cells, header_cells, "row {line:?}");
        }
    }

    let csv = read(&dir.0.join("report.csv"));
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().expect("a header").split(',').collect();
    assert_eq!(header[0], "case");
    let ms = header
        .iter()
        .position(|h| *h == "ms_per_step")
        .expect("ms column");
    let engine = header.iter().position(|h| *h == "engine").expect("engine");
    let mut engines = std::collections::BTreeSet::new();
    for line in lines {
        // The setting may be quoted (it has commas): count from the right.
        let fields: Vec<&str> = line.split(',').collect();
        let n = fields.len();
        assert!(n >= header.len(), "{line}");
        let value: f64 = fields[n - header.len() + ms].parse().expect("a number");
        assert!(value >= 0.0, "{line}");
        engines.insert(fields[engine].to_string());
    }
    if cfg!(feature = "peers") {
        assert_eq!(
            engines.into_iter().collect::<Vec<_>>(),
            ["box2d", "rapier", "tumble"]
        );
        assert!(md.contains("| Box2D | 4 sub |"), "no Box2D rows");
        assert!(md.contains("| Rapier | 4 sub |"), "no Rapier rows");
        assert!(!md.contains("tumble only"));
    } else {
        assert_eq!(engines.into_iter().collect::<Vec<_>>(), ["tumble"]);
        assert!(
            md.contains("tumble only"),
            "the markdown must say it has no peers"
        );
    }
}

#[test]
fn report_refuses_unknown_cases_and_engines() {
    for (args, needle) in [
        (&["report", "--quick", "--cases", "nope"][..], "no case"),
        (
            &["report", "--quick", "--engines", "havok"][..],
            "no engine",
        ),
    ] {
        let out = bench(args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(stderr.contains(needle), "{args:?}: {stderr}");
    }
}
