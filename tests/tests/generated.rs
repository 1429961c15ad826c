//! Property test over generated scenes: whatever the loader accepts simulates 200 steps with
//! no panic and no non-finite number, and whatever it refuses is refused with a message.

use proptest::prelude::*;
use tumble_physics::{BodyDef, BodyKind, Limits, SceneDef, ShapeDef, World};
use tumble_scene::{Format, LoadLimits, parse};
use tumble_tests::all_finite;

fn shape() -> impl Strategy<Value = ShapeDef> {
    prop_oneof![
        (0.02f32..3.0).prop_map(|radius| ShapeDef::Circle { radius }),
        (0.02f32..3.0, 0.02f32..3.0).prop_map(|(hx, hy)| ShapeDef::Box {
            half_extents: [hx, hy],
            radius: 0.0
        }),
        // A regular-ish polygon: n vertices on a circle at increasing angles (convex, CCW),
        // with jittered radii that may make it concave, which the loader must then refuse.
        (
            3usize..=8,
            0.1f32..2.0,
            proptest::collection::vec(0.85f32..1.15, 8)
        )
            .prop_map(|(n, r, jitter)| {
                let vertices = (0..n)
                    .map(|i| {
                        let a = i as f32 / n as f32 * std::f32::consts::TAU;
                        [r * jitter[i] * a.cos(), r * jitter[i] * a.sin()]
                    })
                    .collect();
                ShapeDef::Polygon {
                    vertices,
                    radius: 0.0,
                }
            }),
    ]
}

fn body() -> impl Strategy<Value = BodyDef> {
    (
        shape(),
        prop_oneof![
            Just(BodyKind::Dynamic),
            Just(BodyKind::Dynamic),
            Just(BodyKind::Static),
            Just(BodyKind::Kinematic)
        ],
        (-6.0f32..6.0, 0.0f32..12.0),
        -3.2f32..3.2,
        (-5.0f32..5.0, -5.0f32..5.0),
        -20.0f32..20.0,
        (0.01f32..100.0, 0.0f32..1.5, 0.0f32..1.2),
        (0.0f32..5.0, 0.0f32..5.0, any::<bool>()),
    )
        .prop_map(
            |(
                shape,
                kind,
                (x, y),
                angle,
                (vx, vy),
                w,
                (density, friction, restitution),
                (ld, ad, fixed),
            )| {
                BodyDef::new(shape)
                    .kind(kind)
                    .at(x, y)
                    .angle(angle)
                    .velocity(vx, vy)
                    .spin(w)
                    .density(density)
                    .friction(friction)
                    .restitution(restitution)
                    .damping(ld, ad)
                    .fixed_rotation(fixed)
            },
        )
}

fn scene() -> impl Strategy<Value = SceneDef> {
    (
        proptest::collection::vec(body(), 1..40),
        1u32..9,
        (-20.0f32..20.0, -20.0f32..5.0),
    )
        .prop_map(|(bodies, substeps, (gx, gy))| {
            let mut s = SceneDef::new("generated");
            // A floor and walls so that bodies meet instead of flying apart.
            for (x, y, hx, hy) in [
                (0.0, -1.0, 10.0, 1.0),
                (-10.0, 8.0, 0.5, 10.0),
                (10.0, 8.0, 0.5, 10.0),
            ] {
                s.push(
                    BodyDef::new(ShapeDef::Box {
                        half_extents: [hx, hy],
                        radius: 0.0,
                    })
                    .kind(BodyKind::Static)
                    .at(x, y),
                );
            }
            s.bodies.extend(bodies);
            s.substeps = substeps;
            s.gravity = [gx, gy];
            s
        })
}

proptest! {
    // 48 scenes × 200 steps of up to 40 bodies: a few seconds, enough to shake out panics.
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    #[test]
    fn accepted_scenes_simulate_finitely(scene in scene()) {
        let generated_bodies = scene.bodies.len();
        let json = serde_json::to_vec(&scene).unwrap();
        match parse(&json, Format::Json, "generated.json", &LoadLimits::default()) {
            Ok(loaded) => {
                let mut w = World::from_scene(&loaded, &Limits::default()).unwrap();
                for _ in 0..200 {
                    w.step(loaded.dt, loaded.substeps);
                }
                prop_assert!(all_finite(&w), "non-finite state");
                prop_assert_eq!(w.non_finite_bodies(), 0, "the NaN guard stopped bodies");
                prop_assert_eq!(w.body_count(), generated_bodies);
            }
            // Only a polygon made concave by the jitter may be refused, and the message
            // must say where and why.
            Err(e) => {
                let msg = e.to_string();
                prop_assert!(msg.contains("generated.json") && msg.contains("shape.Polygon.vertices"), "{}", msg);
            }
        }
    }
}
