//! What sleeping bodies cost while something else in the world is awake: the stages walk
//! the awake set only, so a sleeping body should cost nothing. Two worlds: A holds `PILES`
//! resting 20-row pyramids, asleep, and one ball falling freely far from them (always
//! awake); B holds the ball alone. Blocks of steps are timed alternately, A then B, and the
//! median difference per sleeping body printed with the spread. `partly_asleep [PILES]
//! [BLOCKS]`. A measurement, not a test: run it with --release on a quiet machine.
mod common;

use common::{DT, SUBSTEPS, add_pyramid, alternate_blocks, spread};
use tumble_physics::{BodyDef, ShapeDef, StepSettings, World};

const ROWS: usize = 20;

fn world(piles: usize) -> World {
    let mut w = World::new(StepSettings::default());
    w.set_thread_count(1);
    for p in 0..piles {
        add_pyramid(&mut w, ROWS, 50.0 * p as f32);
    }
    // Far below everything, falling for ever: one awake island.
    let ball = BodyDef::new(ShapeDef::Circle { radius: 0.5 }).at(-1000.0, -1000.0);
    w.create_body(&ball).unwrap();
    w
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let piles = args.get(1).map_or(40, |a| a.parse().expect("PILES"));
    let blocks = args.get(2).map_or(21, |a| a.parse().expect("BLOCKS"));
    let mut piled = world(piles);
    let mut alone = world(0);
    let mut settle = 0;
    while piled.awake_body_count() > 1 {
        piled.step(DT, SUBSTEPS);
        settle += 1;
        assert!(settle < 3000, "the piles never fell asleep");
    }
    let sleeping = piled.body_count() - piles - 1;
    let per_block = 200;
    let times = alternate_blocks(&mut piled, &mut alone, blocks, per_block);
    assert_eq!(piled.awake_body_count(), 1, "a pile woke up");
    let extra_ns = times
        .iter()
        .map(|(a, b)| (a - b) * 1e6 / sleeping as f64)
        .collect();
    let (ns, least, most) = spread(extra_ns);
    let (step_ms, _, _) = spread(times.iter().map(|t| t.0).collect());
    println!(
        "{piles} sleeping {ROWS}-row pyramids ({sleeping} bodies, {} contacts) beside one awake \
         ball, asleep after {settle} steps: {ns:.2} ns a step per sleeping body (median of \
         {blocks} blocks of {per_block} steps; min {least:.2}, max {most:.2}); step {step_ms:.4} ms",
        piled.contact_count(),
    );
}
