//! The long soak for a person to run (not CI): `soak_long [BODIES] [STEPS]`, default 20,000
//! bodies for 100,000 steps. Prints resident memory and finiteness every 10% of the run.
use tumble_physics::{BodyDef, BodyKind, Limits, SceneDef, ShapeDef, World};

fn resident_kb() -> u64 {
    let statm = std::fs::read_to_string("/proc/self/statm").unwrap_or_default();
    statm
        .split_whitespace()
        .nth(1)
        .and_then(|p| p.parse::<u64>().ok())
        .unwrap_or(0)
        * 4
}

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let n: usize = a.get(1).map_or(20_000, |s| s.parse().expect("BODIES"));
    let steps: u64 = a.get(2).map_or(100_000, |s| s.parse().expect("STEPS"));
    let mut scene = SceneDef::new("soak_long");
    let half = (n as f32).sqrt() * 0.45 + 5.0;
    let wall = |x: f32, y: f32, hx: f32, hy: f32| {
        BodyDef::new(ShapeDef::Box {
            half_extents: [hx, hy],
        })
        .kind(BodyKind::Static)
        .at(x, y)
    };
    scene.push(wall(0.0, -0.5, half + 1.0, 0.5));
    scene.push(wall(-half - 0.5, 4.0 * half, 0.5, 4.0 * half));
    scene.push(wall(half + 0.5, 4.0 * half, 0.5, 4.0 * half));
    let columns = ((2.0 * half - 2.0) / 0.8) as usize;
    for i in 0..n {
        let x = -half + 1.0 + (i % columns) as f32 * 0.8;
        let y = 1.0 + (i / columns) as f32 * 0.9;
        let shape = if i % 3 == 0 {
            ShapeDef::Box {
                half_extents: [0.3, 0.25],
            }
        } else {
            ShapeDef::Circle { radius: 0.25 }
        };
        scene.push(BodyDef::new(shape).at(x, y));
    }
    let mut w = World::from_scene(&scene, &Limits::default()).expect("scene");
    let t0 = std::time::Instant::now();
    let mut peak = 0;
    for s in 1..=steps {
        w.step(scene.dt, scene.substeps);
        if s % (steps / 10).max(1) == 0 {
            let finite = (0..w.body_count()).all(|i| {
                let b = w.body(i);
                b.position.is_finite() && b.linear_velocity.is_finite()
            });
            peak = peak.max(resident_kb());
            println!(
                "step {s}: {:.0} s wall, resident {} KB (peak {peak} KB), contacts {}, finite {finite}, guard fired {} times, ms/step {:.2}",
                t0.elapsed().as_secs_f64(),
                resident_kb(),
                w.contact_count(),
                w.profile().non_finite,
                w.profile().step_ms
            );
        }
    }
}
