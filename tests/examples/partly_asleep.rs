//! What sleeping bodies cost while something else in the world is awake: sleeping rows are
//! skipped by flags, not moved out of the arrays the stages walk (Box2D's solver sets do),
//! so each still costs a check per stage. Two worlds: A holds `PILES` resting 20-row
//! pyramids, asleep, and one ball falling freely far from them (always awake); B holds the
//! ball alone. Blocks of steps are timed alternately, A then B, and the median difference
//! per sleeping body printed with the spread. `partly_asleep [PILES] [BLOCKS]`. A
//! measurement, not a test: run it with --release on a quiet machine.
use std::time::Instant;

use tumble_physics::{BodyDef, BodyKind, ShapeDef, StepSettings, World};

const ROWS: usize = 20;

fn world(piles: usize) -> World {
    let mut w = World::new(StepSettings::default());
    w.set_thread_count(1);
    for p in 0..piles {
        let x0 = 50.0 * p as f32;
        let ground = BodyDef::new(ShapeDef::Box {
            half_extents: [20.0, 0.5],
        });
        w.create_body(&ground.kind(BodyKind::Static).at(x0, -0.5))
            .unwrap();
        for row in 0..ROWS {
            for col in 0..ROWS - row {
                let x = x0 + col as f32 + 0.5 * row as f32 - 0.5 * ROWS as f32;
                let unit = ShapeDef::Box {
                    half_extents: [0.5, 0.5],
                };
                w.create_body(&BodyDef::new(unit).at(x, 0.5 + row as f32))
                    .unwrap();
            }
        }
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
    let (dt, substeps) = (1.0 / 60.0, 4);
    let mut piled = world(piles);
    let mut alone = world(0);
    let mut settle = 0;
    while piled.awake_body_count() > 1 {
        piled.step(dt, substeps);
        settle += 1;
        assert!(settle < 3000, "the piles never fell asleep");
    }
    let sleeping = piled.live_body_count() - piles - 1;
    let per_block = 200;
    let time = |w: &mut World| {
        let t = Instant::now();
        for _ in 0..per_block {
            w.step(dt, substeps);
        }
        t.elapsed().as_secs_f64() * 1e3 / per_block as f64
    };
    let mut extra_ns = Vec::new();
    let mut piled_ms = Vec::new();
    for _ in 0..blocks {
        let a = time(&mut piled);
        let b = time(&mut alone);
        extra_ns.push((a - b) * 1e6 / sleeping as f64);
        piled_ms.push(a);
    }
    assert_eq!(piled.awake_body_count(), 1, "a pile woke up");
    extra_ns.sort_by(f64::total_cmp);
    piled_ms.sort_by(f64::total_cmp);
    let med = |v: &[f64]| v[v.len() / 2];
    println!(
        "{piles} sleeping {ROWS}-row pyramids ({sleeping} bodies, {} contacts) beside one awake \
         ball, asleep after {settle} steps: {:.2} ns a step per sleeping body (median of \
         {blocks} blocks of {per_block} steps; min {:.2}, max {:.2}); step {:.4} ms",
        piled.contact_count(),
        med(&extra_ns),
        extra_ns[0],
        extra_ns[extra_ns.len() - 1],
        med(&piled_ms)
    );
}
