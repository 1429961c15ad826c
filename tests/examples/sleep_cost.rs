//! What a sleeping pile costs against the same pile awake (issue 15's target: a resting
//! 20-row pyramid, asleep, at most 5% of its awake step). Two worlds of the same pyramid,
//! one with sleeping on and one off, stepped until the first sleeps; then blocks of steps
//! timed alternately, A then B, and the median of the per-block ratios printed with the
//! spread. `sleep_cost [ROWS] [BLOCKS]`. A measurement, not a test: run it with --release on
//! a quiet machine.
mod common;

use common::{DT, SUBSTEPS, add_pyramid, alternate_blocks, spread};
use tumble_physics::{StepSettings, World};

fn pyramid(rows: usize, sleep: bool) -> World {
    let settings = StepSettings {
        enable_sleep: sleep,
        ..StepSettings::default()
    };
    let mut w = World::new(settings);
    w.set_thread_count(1);
    add_pyramid(&mut w, rows, 0.0);
    w
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let rows = args.get(1).map_or(20, |a| a.parse().expect("ROWS"));
    let blocks = args.get(2).map_or(21, |a| a.parse().expect("BLOCKS"));
    let mut asleep = pyramid(rows, true);
    let mut awake = pyramid(rows, false);
    let mut settle = 0;
    while asleep.awake_body_count() > 0 {
        asleep.step(DT, SUBSTEPS);
        awake.step(DT, SUBSTEPS);
        settle += 1;
        assert!(settle < 3000, "the pyramid never fell asleep");
    }
    let per_block = 200;
    let times = alternate_blocks(&mut asleep, &mut awake, blocks, per_block);
    let (ratio, least, most) = spread(times.iter().map(|(a, b)| a / b).collect());
    let (awake_ms, _, _) = spread(times.iter().map(|t| t.1).collect());
    println!(
        "{rows}-row pyramid ({} bodies), asleep after {settle} steps: asleep / awake step = \
         {ratio:.4} (median of {blocks} blocks of {per_block} steps; min {least:.4}, max \
         {most:.4}); awake step {awake_ms:.4} ms",
        asleep.body_count(),
    );
}
