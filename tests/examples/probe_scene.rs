use tumble_physics::*;
fn main() {
    let a: Vec<String> = std::env::args().collect();
    let scene = tumble_scene::builtin::build(&a[1]).unwrap();
    let steps: u32 = a.get(2).map(|s| s.parse().unwrap()).unwrap_or(scene.steps);
    let hz: f32 = a.get(3).map(|s| s.parse().unwrap()).unwrap_or(60.0);
    let sub: u32 = a
        .get(4)
        .map(|s| s.parse().unwrap())
        .unwrap_or(scene.substeps);
    let ws: bool = a.get(5).map(|s| s == "1").unwrap_or(true);
    let mut w = World::from_scene(&scene, &Limits::default()).unwrap();
    w.settings_mut().contact_hertz = hz;
    w.settings_mut().warm_starting = ws;
    let init: Vec<_> = (0..w.body_count()).map(|i| w.body(i).position).collect();
    for s in 1..=steps {
        w.step(scene.dt, sub);
        if s % (steps / 5).max(1) == 0 {
            let mut maxv = (0.0f32, 0usize);
            let mut maxd = (0.0f32, 0usize);
            for i in 0..w.body_count() {
                let b = w.body(i);
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
                "step {s}: max v {:.3} (body {} at {:?}) max disp {:.3} (body {}) contacts {} touching {} colors {} overflow {} ms {:.2}",
                maxv.0,
                maxv.1,
                w.body(maxv.1).position,
                maxd.0,
                maxd.1,
                p.contacts,
                p.touching,
                p.colors,
                p.overflow,
                p.step_ms
            );
        }
    }
}
