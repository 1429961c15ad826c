//! `tumble-bench rays` on a small scene: it exits 0 only when the tree and the scan of every
//! shape found the same nearest hit for every ray, and writes its table.

use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_tumble-bench");

#[test]
fn rays_through_the_tree_find_what_a_scan_finds() {
    let out = Command::new(BIN)
        .args(["rays", "--scene", "large_pyramid", "--steps", "30"])
        .args(["--rays", "300", "--repeats", "1"])
        .output()
        .expect("the tumble-bench binary runs");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(stdout.contains("| tree (`cast_ray_closest`) |"), "{stdout}");
    // The rays cross the pyramid's lower half: nearly all hit something (a ray near the top
    // sloping up can pass over it), so the agreement is about real hits.
    let hits: u32 = stdout
        .split(" of 300 hit something")
        .next()
        .and_then(|head| head.rsplit('(').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no hit count in {stdout}"));
    assert!(hits > 250, "{hits} of 300 rays hit");
}
