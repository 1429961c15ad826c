//! A short soak: 2,000 bodies for 5,000 steps (83 s of simulated time) must stay finite and
//! keep its memory bounded. The long version (`tumble-bench soak`: 20,000 bodies, 100,000
//! steps) is for a person to run, not CI; its figures are in docs/architecture.md, Reliability.

use tumble_physics::{Limits, World};
use tumble_scene::builtin::soak_pile;
use tumble_tests::all_finite;

/// Resident memory of this process in bytes, from /proc (Linux, where CI runs).
fn resident_bytes() -> u64 {
    let statm = std::fs::read_to_string("/proc/self/statm").expect("/proc/self/statm");
    let pages: u64 = statm.split_whitespace().nth(1).unwrap().parse().unwrap();
    pages * 4096
}

#[test]
fn two_thousand_bodies_for_five_thousand_steps() {
    // 2,000 circles and boxes dropped into a closed 40 m box (the pile of `tumble-bench soak`).
    let scene = soak_pile(2000);
    let mut w = World::from_scene(&scene, &Limits::default()).unwrap();
    w.set_thread_count(2);
    // Warm up: buffers reach their working size while the pile forms.
    for _ in 0..1000 {
        w.step(scene.dt, scene.substeps);
    }
    let warm = resident_bytes();
    let mut peak = warm;
    let mut max_contacts = 0;
    for step in 1000..5000 {
        w.step(scene.dt, scene.substeps);
        if step % 250 == 0 {
            assert!(all_finite(&w), "non-finite state at step {step}");
            peak = peak.max(resident_bytes());
            max_contacts = max_contacts.max(w.contact_count());
        }
    }
    assert!(all_finite(&w));
    assert_eq!(w.non_finite_bodies(), 0, "the NaN guard stopped bodies");
    assert!(
        max_contacts > 2000,
        "the pile never formed: {max_contacts} contacts"
    );
    // Every per-step buffer is reused, so after warm-up memory may only wobble: contact
    // arrays grow geometrically when a heap shifts (one doubling of the ~1 MB of contact
    // and constraint buffers), so allow 8 MB or 25% of the warm size, whichever is larger.
    let growth = peak.saturating_sub(warm);
    let allowed = (8 << 20).max(warm / 4);
    eprintln!(
        "soak: warm {} KB, peak {} KB, {max_contacts} contacts at most",
        warm >> 10,
        peak >> 10
    );
    assert!(
        growth <= allowed,
        "memory grew by {} KB (allowed {} KB)",
        growth >> 10,
        allowed >> 10
    );
}
