use tumble_physics::*;
fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .map(|s| s.parse().unwrap())
        .unwrap_or(5);
    let fr: f32 = std::env::args()
        .nth(2)
        .map(|s| s.parse().unwrap())
        .unwrap_or(0.3);
    let mut scene = SceneDef::new("probe");
    scene.push(
        BodyDef::new(ShapeDef::Box {
            half_extents: [20.0, 0.5],
        })
        .kind(BodyKind::Static)
        .at(0.0, -0.5)
        .friction(fr),
    );
    for i in 0..n {
        let x = if i % 2 == 0 { -0.01 } else { 0.01 };
        scene.push(
            BodyDef::new(ShapeDef::Box {
                half_extents: [0.5, 0.5],
            })
            .at(x, 0.5 + i as f32)
            .friction(fr),
        );
    }
    let mut w = World::from_scene(&scene, &Limits::default()).unwrap();
    let sub: u32 = std::env::args()
        .nth(3)
        .map(|s| s.parse().unwrap())
        .unwrap_or(4);
    w.settings_mut().contact_hertz = std::env::args()
        .nth(4)
        .map(|s| s.parse().unwrap())
        .unwrap_or(30.0);
    w.settings_mut().relax_iterations = std::env::args()
        .nth(5)
        .map(|s| s.parse().unwrap())
        .unwrap_or(1);
    w.set_thread_count(1);
    for step in 0..=1200 {
        if step % 200 == 0 {
            let b = w.body(n);
            println!(
                "recycled {} of {} step {step}: top x {:.4} y {:.4} angle {:.5} v {:?}",
                w.profile().recycled,
                w.profile().contacts,
                b.position.x,
                b.position.y,
                b.angle,
                b.linear_velocity
            );
            if step == 200 && false {
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
        w.step(1.0 / 60.0, sub);
    }
}
