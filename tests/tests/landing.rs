//! Flat landings stay straight (issue 36) at the defaults, which solve a manifold's two points
//! together (`StepSettings::solve_points_together`): a body dropped flat onto flat ground
//! lands with no sideways motion and no turn, whatever the height, for boxes, capsules and
//! rounded boxes, in the scalar and the SIMD solvers. Solved in turn (the setting off, Box2D's
//! Soft Step), the first of a manifold's two points takes the whole impact and friction at it
//! alone pushes the body sideways: up to 1.4 m/s and 2.8 rad/s
//! (docs/accuracy/flat_landing.md), which the second test shows.

use tumble_physics::{BodyDef, BodyKind, ShapeDef, StepSettings, World};

/// Drops `shape` flat with its bottom `height` metres above the ground and steps 6.7 s;
/// returns the largest sideways speed and spin after touchdown, and the final x and angle.
fn drop(
    shape: &ShapeDef,
    bottom_offset: f32,
    height: f32,
    simd: bool,
    together: bool,
) -> (f32, f32, f32, f32) {
    let mut w = World::new(StepSettings {
        simd,
        solve_points_together: together,
        ..StepSettings::default()
    });
    w.create_body(
        &BodyDef::new(ShapeDef::Box {
            half_extents: [40.0, 0.5],
            radius: 0.0,
        })
        .kind(BodyKind::Static)
        .at(0.0, -0.5),
    )
    .unwrap();
    let b = w
        .create_body(
            &BodyDef::new(shape.clone())
                .at(0.0, height + bottom_offset)
                .friction(0.6),
        )
        .unwrap();
    let (mut vx, mut spin) = (0.0f32, 0.0f32);
    for _ in 0..400 {
        w.step(1.0 / 60.0, 4);
        let v = w.body(b).unwrap();
        vx = vx.max(v.linear_velocity.x.abs());
        spin = spin.max(v.angular_velocity.abs());
    }
    assert_eq!(w.non_finite_bodies(), 0);
    let v = w.body(b).unwrap();
    (vx, spin, v.position.x, v.angle)
}

#[test]
fn boxes_capsules_and_rounded_boxes_dropped_flat_land_straight() {
    // (shape, its half height): a 2 m box, a capsule 2 m long lying down, a rounded box.
    let shapes = [
        (
            "box",
            ShapeDef::Box {
                half_extents: [1.0, 1.0],
                radius: 0.0,
            },
            1.0,
        ),
        (
            "capsule",
            ShapeDef::Capsule {
                center1: [-0.75, 0.0],
                center2: [0.75, 0.0],
                radius: 0.25,
            },
            0.25,
        ),
        (
            "rounded box",
            ShapeDef::Box {
                half_extents: [0.9, 0.9],
                radius: 0.1,
            },
            1.0,
        ),
    ];
    // The defaults solve the points together.
    let together = StepSettings::default().solve_points_together;
    assert!(together);
    for (name, shape, half_height) in &shapes {
        for height in [1.0, 3.0, 10.0, 20.0] {
            for simd in [false, true] {
                let (vx, spin, x, angle) = drop(shape, *half_height, height, simd, together);
                // The bounds: sideways speed under 5 cm/s at every step, the final
                // offset and angle under 1 cm and 0.01 rad (measured: 0 for every case).
                let case = format!("{name} from {height} m (simd {simd})");
                assert!(vx < 0.05, "{case}: sideways at {vx} m/s");
                assert!(spin < 0.05, "{case}: turning at {spin} rad/s");
                assert!(
                    x.abs() < 0.01 && angle.abs() < 0.01,
                    "{case}: ends at {x} m, {angle} rad"
                );
            }
        }
    }
}

#[test]
fn in_turn_as_box2d_solves_them_a_box_dropped_flat_lands_sideways() {
    // Box2D's rule: the defect the setting mends, so that the test above shows something
    // (measured: 0.54 m/s sideways and 0.53 rad/s for a 2 m box from 3 m).
    let shape = ShapeDef::Box {
        half_extents: [1.0, 1.0],
        radius: 0.0,
    };
    let (vx, spin, _, _) = drop(&shape, 1.0, 3.0, true, false);
    assert!(vx > 0.3 && spin > 0.3, "{vx} m/s, {spin} rad/s");
}
