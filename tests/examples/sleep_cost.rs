//! What a sleeping pile costs against the same pile awake (issue 15's target: a resting
//! 20-row pyramid, asleep, at most 5% of its awake step). Two worlds of the same pyramid,
//! one with sleeping on and one off, stepped until the first sleeps; then blocks of steps
//! timed alternately, A then B, and the median of the per-block ratios printed with the
//! spread. `sleep_cost [ROWS] [BLOCKS]`. A measurement, not a test: run it with --release on
//! a quiet machine.
use std::time::Instant;

use tumble_physics::{BodyDef, BodyKind, ShapeDef, StepSettings, World};

fn pyramid(rows: usize, sleep: bool) -> World {
    let settings = StepSettings {
        enable_sleep: sleep,
        ..StepSettings::default()
    };
    let mut w = World::new(settings);
    w.set_thread_count(1);
    let ground = BodyDef::new(ShapeDef::Box {
        half_extents: [40.0, 0.5],
    });
    w.create_body(&ground.kind(BodyKind::Static).at(0.0, -0.5))
        .unwrap();
    for row in 0..rows {
        for col in 0..rows - row {
            let x = col as f32 + 0.5 * row as f32 - 0.5 * rows as f32;
            let unit = ShapeDef::Box {
                half_extents: [0.5, 0.5],
            };
            w.create_body(&BodyDef::new(unit).at(x, 0.5 + row as f32))
                .unwrap();
        }
    }
    w
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let rows = args.get(1).map_or(20, |a| a.parse().expect("ROWS"));
    let blocks = args.get(2).map_or(21, |a| a.parse().expect("BLOCKS"));
    let (dt, substeps) = (1.0 / 60.0, 4);
    let mut asleep = pyramid(rows, true);
    let mut awake = pyramid(rows, false);
    let mut settle = 0;
    while asleep.awake_body_count() > 0 {
        asleep.step(dt, substeps);
        awake.step(dt, substeps);
        settle += 1;
        assert!(settle < 3000, "the pyramid never fell asleep");
    }
    let per_block = 200;
    let time = |w: &mut World| {
        let t = Instant::now();
        for _ in 0..per_block {
            w.step(dt, substeps);
        }
        t.elapsed().as_secs_f64() * 1e3 / per_block as f64
    };
    let mut ratios = Vec::new();
    let mut awake_ms = Vec::new();
    for _ in 0..blocks {
        let a = time(&mut asleep);
        let b = time(&mut awake);
        ratios.push(a / b);
        awake_ms.push(b);
    }
    ratios.sort_by(f64::total_cmp);
    awake_ms.sort_by(f64::total_cmp);
    let med = |v: &[f64]| v[v.len() / 2];
    println!(
        "{rows}-row pyramid ({} bodies), asleep after {settle} steps: asleep / awake step = {:.4} \
         (median of {blocks} blocks of {per_block} steps; min {:.4}, max {:.4}); awake step {:.4} ms",
        asleep.live_body_count(),
        med(&ratios),
        ratios[0],
        ratios[ratios.len() - 1],
        med(&awake_ms)
    );
}
