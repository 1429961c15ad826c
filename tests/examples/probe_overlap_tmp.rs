use tumble_physics::*;
fn main() {
    let a: Vec<String> = std::env::args().collect();
    let hz: f32 = a.get(1).map(|s| s.parse().unwrap()).unwrap_or(60.0);
    let relax: u32 = a.get(2).map(|s| s.parse().unwrap()).unwrap_or(1);
    let sub: u32 = a.get(3).map(|s| s.parse().unwrap()).unwrap_or(4);
    let scene = tumble_scene::builtin::build("overlap_recovery").unwrap();
    let mut w = World::from_scene(&scene, &Limits::default()).unwrap();
    w.settings_mut().contact_hertz = hz;
    w.settings_mut().relax_iterations = relax;
    let mut topmax = f32::MIN;
    let mut overall = (0.0f32, 0, 0);
    for s in 0..600 {
        w.step(scene.dt, sub);
        let mut peak = (0.0f32, 0);
        for i in 0..w.body_count() {
            let v = w.body(i).linear_velocity.length();
            if v > peak.0 {
                peak = (v, i);
            }
        }
        topmax = topmax.max(w.body(10).position.y);
        if peak.0 > overall.0 {
            overall = (peak.0, s, peak.1);
        }
        let mut maxrel = 0.0f32;
        let mut deepest = 0.0f32;
        for c in w.contacts() {
            for p in c.manifold.points() {
                deepest = deepest.min(p.separation);
            }
            let (ba, bb) = (w.body(c.body_a), w.body(c.body_b));
            let rv = (bb.linear_velocity - ba.linear_velocity).dot(c.manifold.normal);
            maxrel = maxrel.max(rv);
        }
        if s < 12 || s % 60 == 0 {
            println!(
                "step {s}: peak {:.3} body {} | max rel normal v (centres) {:.3} | deepest {:.4} | top {:?}",
                peak.0,
                peak.1,
                maxrel,
                deepest,
                w.body(10).position
            );
        }
    }
    println!(
        "overall peak {:?} top max y {} final {}",
        overall,
        topmax,
        w.body(10).position.y
    );
}
