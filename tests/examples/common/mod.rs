//! What the sleep measurements share: a pyramid of unit boxes, and two worlds timed in
//! alternating blocks of steps (so that a drift in the machine's speed falls on both).
use std::time::Instant;

use tumble_physics::{BodyDef, BodyKind, ShapeDef, World};

/// Box2D's step: 60 Hz, 4 substeps.
pub const DT: f32 = 1.0 / 60.0;
pub const SUBSTEPS: u32 = 4;

/// Adds a `rows`-row pyramid of unit boxes centred on `x0`, on a static ground 40 m wide.
pub fn add_pyramid(w: &mut World, rows: usize, x0: f32) {
    let ground = BodyDef::new(ShapeDef::Box {
        half_extents: [20.0, 0.5],
        radius: 0.0,
    });
    w.create_body(&ground.kind(BodyKind::Static).at(x0, -0.5))
        .unwrap();
    for row in 0..rows {
        for col in 0..rows - row {
            let x = x0 + col as f32 + 0.5 * row as f32 - 0.5 * rows as f32;
            let unit = ShapeDef::Box {
                half_extents: [0.5, 0.5],
                radius: 0.0,
            };
            w.create_body(&BodyDef::new(unit).at(x, 0.5 + row as f32))
                .unwrap();
        }
    }
}

/// Steps `a` then `b`, `blocks` times, `per_block` steps each, and returns each block's mean
/// ms per step as (a, b).
pub fn alternate_blocks(
    a: &mut World,
    b: &mut World,
    blocks: usize,
    per_block: usize,
) -> Vec<(f64, f64)> {
    let time = |w: &mut World| {
        let t = Instant::now();
        for _ in 0..per_block {
            w.step(DT, SUBSTEPS);
        }
        t.elapsed().as_secs_f64() * 1e3 / per_block as f64
    };
    (0..blocks).map(|_| (time(a), time(b))).collect()
}

/// The median, the smallest and the largest of `v`.
pub fn spread(mut v: Vec<f64>) -> (f64, f64, f64) {
    v.sort_by(f64::total_cmp);
    (v[v.len() / 2], v[0], v[v.len() - 1])
}
