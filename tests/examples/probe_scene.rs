//! Steps a built-in scene and prints how still it is: `probe_scene NAME [STEPS] [HZ] [SUBSTEPS]`.
use tumble_physics::BodyId;
use tumble_physics::*;
fn main() {
    let a: Vec<String> = std::env::args().collect();
    let scene = tumble_scene::builtin::build(&a[1]).expect("a built-in scene name");
    let steps: u32 = a.get(2).map_or(scene.steps, |s| s.parse().unwrap());
    let hz: f32 = a.get(3).map_or(30.0, |s| s.parse().unwrap());
    let sub: u32 = a.get(4).map_or(scene.substeps, |s| s.parse().unwrap());
    let mut w = World::from_scene(&scene, &Limits::default()).unwrap();
    w.settings_mut().contact_hertz = hz;
    w.settings_mut().contact_recycling = std::env::var("NORECYCLE").is_err();
    let init: Vec<_> = (0..w.body_count())
        .map(|i| w.body(BodyId::scene(i)).unwrap().position)
        .collect();
    for s in 1..=steps {
        w.step(scene.dt, sub);
        if s % (steps / 10).max(1) == 0 {
            let (mut maxv, mut maxd) = ((0.0f32, 0usize), (0.0f32, 0usize));
            for i in 0..w.body_count() {
                let b = w.body(BodyId::scene(i)).unwrap();
                let v = b.linear_velocity.length();
                if v > maxv.0 {
                    maxv = (v, i);
                }
                let d = (b.position - init[i]).length();
                if d > maxd.0 {
                    maxd = (d, i);
                }
            }
            let p = w.profile();
            println!(
                "step {s}: max v {:.4} (body {}) max disp {:.3} (body {}) contacts {} touching {} recycled {} moved {} colors {} overflow {} ms {:.2} bp {:.3}",
                maxv.0,
                maxv.1,
                maxd.0,
                maxd.1,
                p.contacts,
                p.touching,
                p.recycled,
                p.moved,
                p.colors,
                p.overflow,
                p.step_ms,
                p.broad_phase_ms
            );
        }
    }
}
