//! Capsules, segments, chains and rounded polygons in scenes: what each is for (ground that
//! does not snag, bodies that rest and bounce as their closed forms say, one-sided walls).

use tumble_physics::BodyId;
use tumble_physics::{BodyDef, BodyKind, PartDef, SceneDef, ShapeDef};
use tumble_tests::{all_finite, run, world};

/// The Soft Step pushes contacts apart only beyond the linear slop (5 mm, Box2D's
/// `B2_LINEAR_SLOP`): a body at rest sinks into its support by up to that much.
const SLOP: f32 = 0.005;

/// Flat ground from x = 50 to x = -50 (right to left, so a chain pushes up) of 0.1 m pieces:
/// one chain, or as many separate two-sided segments.
fn flat_ground(chain: bool) -> BodyDef {
    let xs: Vec<f32> = (0..=1000).map(|i| 50.0 - 0.1 * i as f32).collect();
    let parts = if chain {
        // The ends are ghosts only: one more point each side.
        let mut points = vec![[50.1, 0.0]];
        points.extend(xs.iter().map(|&x| [x, 0.0]));
        points.push([-50.1, 0.0]);
        vec![PartDef::new(ShapeDef::Chain {
            points,
            looped: false,
        })]
    } else {
        xs.windows(2)
            .map(|w| {
                PartDef::new(ShapeDef::Segment {
                    point1: [w[0], 0.0],
                    point2: [w[1], 0.0],
                })
            })
            .collect()
    };
    let mut ground = BodyDef::compound(parts).kind(BodyKind::Static);
    ground.friction = 0.0;
    ground
}

/// A frictionless unit box sliding at 5 m/s across 250 joints of 0.1 m ground pieces for 5 s;
/// its state at the end.
fn slide(chain: bool) -> (f32, f32, f32, f32) {
    let mut scene = SceneDef::new(if chain {
        "chain slide"
    } else {
        "segment slide"
    });
    scene.push(flat_ground(chain));
    let mut bx = BodyDef::new(ShapeDef::Box {
        half_extents: [0.5, 0.5],
        radius: 0.0,
    })
    .at(-40.0, 0.5 - SLOP)
    .velocity(5.0, 0.0);
    bx.friction = 0.0;
    scene.push(bx);
    let mut w = world(&scene);
    run(&mut w, &scene, 300);
    assert!(all_finite(&w));
    let b = w.body(BodyId::scene(1)).unwrap();
    (
        b.linear_velocity.x,
        b.linear_velocity.y,
        b.rotation.angle(),
        b.position.y,
    )
}

#[test]
fn a_box_slides_along_a_chain_without_snagging() {
    // Frictionless: the closed form is uniform motion at 5 m/s, level. Across a chain every
    // joint is smooth (the ghost vertices), so the box keeps its speed and angle to within
    // the solver's settling (1e-3 of the speed, 1 mrad).
    let (vx, vy, angle, y) = slide(true);
    assert!((vx - 5.0).abs() < 5e-3, "vx {vx}");
    assert!(vy.abs() < 5e-3, "vy {vy}");
    assert!(angle.abs() < 1e-3, "angle {angle}");
    assert!((y - 0.5).abs() <= 2.0 * SLOP, "y {y}");
    // The same ground as 1000 separate two-sided segments: each joint's end vertex meets the
    // box's leading face first (a sideways speculative contact), so the box catches on them.
    let (vx_seg, vy_seg, angle_seg, _) = slide(false);
    eprintln!(
        "after 5 s: chain vx {vx} vy {vy} angle {angle}; segments vx {vx_seg} vy {vy_seg} angle {angle_seg}"
    );
    assert!(
        vx_seg < vx - 0.1,
        "separate segments should snag: {vx_seg} against the chain's {vx}"
    );
}

#[test]
fn capsules_and_rounded_boxes_rest_at_their_rounded_height() {
    // A capsule (radius 0.25) lying on a segment rests with its core 0.25 up; a unit box
    // rounded by 0.1 with its core's centre 0.6 up; each sunk by at most the slop.
    let mut scene = SceneDef::new("rest heights");
    scene.push(
        BodyDef::new(ShapeDef::Segment {
            point1: [-20.0, 0.0],
            point2: [20.0, 0.0],
        })
        .kind(BodyKind::Static),
    );
    scene.push(
        BodyDef::new(ShapeDef::Capsule {
            center1: [-0.5, 0.0],
            center2: [0.5, 0.0],
            radius: 0.25,
        })
        .at(-3.0, 1.0),
    );
    scene.push(
        BodyDef::new(ShapeDef::Box {
            half_extents: [0.5, 0.5],
            radius: 0.1,
        })
        .at(3.0, 1.5),
    );
    let mut w = world(&scene);
    run(&mut w, &scene, 180);
    assert!(all_finite(&w));
    for (index, height) in [(1, 0.25f32), (2, 0.6)] {
        let b = w.body(BodyId::scene(index)).unwrap();
        let sink = height - b.position.y;
        assert!(
            (-1e-3..=SLOP + 1e-3).contains(&sink),
            "body {index}: y {} for a rest height {height}",
            b.position.y
        );
        assert!(b.linear_velocity.length() < 1e-2 && b.rotation.angle().abs() < 1e-3);
    }
}

#[test]
fn capsules_meeting_head_on_elastically_swap_velocities() {
    // Two equal capsules end to end along x, restitution 1, no gravity: momentum and energy
    // conservation give v1' = v2 and v2' = v1 (closed form of a 1-D elastic collision of equal
    // masses). Box2D's restitution acts on the normal speed before the solve, so the swap is
    // exact to the solver's relax pass: 1 % here.
    let mut scene = SceneDef::new("capsule collision");
    scene.gravity = [0.0, 0.0];
    let capsule = ShapeDef::Capsule {
        center1: [-0.5, 0.0],
        center2: [0.5, 0.0],
        radius: 0.25,
    };
    scene.push(
        BodyDef::new(capsule.clone())
            .at(-2.0, 0.0)
            .velocity(3.0, 0.0)
            .restitution(1.0)
            .friction(0.0),
    );
    scene.push(
        BodyDef::new(capsule)
            .at(2.0, 0.0)
            .velocity(-1.0, 0.0)
            .restitution(1.0)
            .friction(0.0),
    );
    let mut w = world(&scene);
    run(&mut w, &scene, 120);
    let (a, b) = (
        w.body(BodyId::scene(0)).unwrap().linear_velocity,
        w.body(BodyId::scene(1)).unwrap().linear_velocity,
    );
    assert!(
        (a.x + 1.0).abs() < 0.03 && (b.x - 3.0).abs() < 0.03,
        "{a} {b}"
    );
    assert!(a.y.abs() < 1e-4 && b.y.abs() < 1e-4);
}

#[test]
fn a_chain_pushes_only_from_its_right_hand_side() {
    // A ball thrown up at 12 m/s from under a flat chain passes through it (the chain pushes
    // only up), rises 7.2 m (v²/2g), falls back and lands on top, where it rests.
    let mut scene = SceneDef::new("one-sided");
    scene.push(flat_ground(true));
    scene.push(
        BodyDef::new(ShapeDef::Circle { radius: 0.5 })
            .at(0.0, -1.0)
            .velocity(0.0, 12.0),
    );
    let mut w = world(&scene);
    let mut highest = f32::MIN;
    for _ in 0..300 {
        w.step(scene.dt, scene.substeps);
        highest = highest.max(w.body(BodyId::scene(1)).unwrap().position.y);
    }
    // 7.2 m above the start, less the symplectic Euler's first-step drop (g·dt² per step).
    assert!((highest - 6.2).abs() < 0.1, "highest {highest}");
    let b = w.body(BodyId::scene(1)).unwrap();
    assert!(
        (b.position.y - 0.5).abs() <= SLOP + 1e-3,
        "rests at {}",
        b.position.y
    );
}

#[test]
fn a_ring_chain_holds_a_pile() {
    // spinner's ring (a 360-point loop, clockwise so it pushes inwards) with its paddle
    // still (static, its motor gone): every body that falls into it stays inside the 40 m
    // circle.
    let mut scene = tumble_scene::builtin::build("spinner").expect("spinner");
    scene.joints.clear();
    scene.bodies[1].kind = tumble_physics::BodyKind::Static;
    scene.bodies.truncate(2 + 900);
    let mut w = world(&scene);
    run(&mut w, &scene, 240);
    assert!(all_finite(&w));
    for i in 2..w.body_count() {
        let p = w.body(BodyId::scene(i)).unwrap().position;
        let r = (p - tumble_physics::Vec2::new(0.0, 32.0)).length();
        assert!(r < 40.0, "body {i} at {p} is {r} m from the ring's centre");
    }
}
