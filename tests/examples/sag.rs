//! Top-box sag and deepest overlap of a built-in pyramid at given settings:
//! `sag NAME STEPS SUBSTEPS HERTZ RELAX`.
use tumble_physics::BodyId;
use tumble_physics::*;
fn main() {
    let a: Vec<String> = std::env::args().collect();
    let scene = tumble_scene::builtin::build(&a[1]).expect("a built-in scene name");
    let steps: u32 = a[2].parse().unwrap();
    let sub: u32 = a[3].parse().unwrap();
    let mut w = World::from_scene(&scene, &Limits::default()).unwrap();
    w.settings_mut().contact_hertz = a[4].parse().unwrap();
    w.settings_mut().relax_iterations = a[5].parse().unwrap();
    let top = w.body_count() - 1;
    let y0 = w.body(BodyId::scene(top)).unwrap().position.y;
    let t = std::time::Instant::now();
    for _ in 0..steps {
        w.step(scene.dt, sub);
    }
    let ms = t.elapsed().as_secs_f64() * 1e3 / steps as f64;
    let deepest = w
        .contacts()
        .flat_map(|c| {
            c.manifold
                .points()
                .iter()
                .map(|p| p.separation)
                .collect::<Vec<_>>()
        })
        .fold(0.0f32, f32::min);
    let vmax = (0..w.body_count())
        .map(|i| w.body(BodyId::scene(i)).unwrap().linear_velocity.length())
        .fold(0.0f32, f32::max);
    println!(
        "{} sub {sub} hz {} relax {}: sag {:.4} m, deepest {:.4} m, max v {:.4}, {:.2} ms/step",
        a[1],
        a[4],
        a[5],
        y0 - w.body(BodyId::scene(top)).unwrap().position.y,
        -deepest,
        vmax,
        ms
    );
}
