//! The viewer's command line refuses bad input before any window opens: exit code 2, one
//! line on stderr, never a panic (CONTRACT.md, section 3).

use std::process::Command;

fn tumble(args: &[&str]) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_tumble"))
        .args(args)
        // No display: a bad flag must be refused before the window is even tried.
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .expect("run tumble");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn bad_flags_and_scenes_exit_2_with_a_message() {
    let cases: &[(&[&str], &str)] = &[
        (&["--scene", "no_such_scene"], "no_such_scene"),
        (&["--scene", "/nonexistent/scene.ron"], "scene.ron"),
        (&["--threads", "0"], "--threads"),
        (&["--threads", "-3"], "--threads"),
        (&["--frames", "0"], "--frames"),
        (&["--frames", "many"], "--frames"),
        (
            &[
                "--screenshot",
                "/nonexistent/dir/shot.png",
                "--scene",
                "pyramid",
            ],
            "does not exist",
        ),
        (
            &["--stats", "/nonexistent/dir/stats.json"],
            "does not exist",
        ),
        (&["--no-such-flag"], "--no-such-flag"),
        (
            &["--scene", "platformer", "--keys", "5:fly+"],
            "unknown key",
        ),
        (
            &["--scene", "platformer", "--keys", "x:right+"],
            "STEP:KEY+",
        ),
        (&["--keys", "0:right+"], "--scene"),
        (&["--scene", "platformer", "--steps", "0"], "--steps"),
        (&["--steps", "10"], "--scene"),
    ];
    for (args, mention) in cases {
        let (code, stderr) = tumble(args);
        assert_eq!(code, 2, "{args:?}: exit {code}, stderr: {stderr}");
        assert!(stderr.contains("error"), "{args:?}: {stderr}");
        assert!(
            stderr.contains(mention),
            "{args:?} should mention {mention}: {stderr}"
        );
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
    }
}

#[test]
fn help_exits_0() {
    let out = Command::new(env!("CARGO_BIN_EXE_tumble"))
        .arg("--help")
        .output()
        .expect("run tumble");
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    for flag in [
        "--scene",
        "--threads",
        "--frames",
        "--screenshot",
        "--stats",
    ] {
        assert!(text.contains(flag), "{flag} missing from --help");
    }
}
