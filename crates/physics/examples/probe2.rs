use tumble_physics::*;
fn main() {
    let mode: u32 = std::env::args()
        .nth(1)
        .map(|s| s.parse().unwrap())
        .unwrap_or(0);
    let mut scene = SceneDef::new("probe");
    scene.push(
        BodyDef::new(ShapeDef::Box {
            half_extents: [20.0, 0.5],
        })
        .kind(BodyKind::Static)
        .at(0.0, -0.5),
    );
    let rows = mode as i32;
    for i in 0..rows {
        for j in i..rows {
            let x = (i as f32 + 1.0) * 0.5 + (j - i) as f32 - 0.5 * rows as f32;
            scene.push(
                BodyDef::new(ShapeDef::Box {
                    half_extents: [0.5, 0.5],
                })
                .at(x, 0.5 + i as f32),
            );
        }
    }
    let mut w = World::from_scene(&scene, &Limits::default()).unwrap();
    w.set_thread_count(1);
    w.settings_mut().contact_hertz = std::env::args()
        .nth(3)
        .map(|s| s.parse().unwrap())
        .unwrap_or(60.0);
    let every: u32 = std::env::args()
        .nth(2)
        .map(|s| s.parse().unwrap())
        .unwrap_or(30);
    for step in 1..=240 {
        w.step(1.0 / 60.0, 4);
        if step % every == 0 {
            let mut mv = 0.0f32;
            let mut mw = 0.0f32;
            let mut bi = 0;
            for i in 1..w.body_count() {
                if w.body(i).linear_velocity.length() > mv {
                    bi = i;
                }
                mv = mv.max(w.body(i).linear_velocity.length());
                mw = mw.max(w.body(i).angular_velocity.abs());
            }
            println!(
                "step {step}: max v {mv:.5} max w {mw:.5} body {bi} {:?}",
                w.body(bi)
            );
        }
    }
    if false {
        for c in w.contacts() {
            println!(
                "  {}-{} n {:?} pts {:?}",
                c.body_a,
                c.body_b,
                c.manifold.normal,
                c.manifold
                    .points()
                    .iter()
                    .map(|p| (
                        p.id,
                        p.point,
                        p.separation,
                        p.normal_impulse,
                        p.tangent_impulse
                    ))
                    .collect::<Vec<_>>()
            );
        }
    }
}
