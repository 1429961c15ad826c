//! A rope bridge of planks on hinges that breaks under a heavy load: every hinge reports
//! when it pulls with more than its force threshold (`Event::JointThreshold`), and the game
//! decides to break it by destroying the joint.
//!
//! `cargo run -p tumble-physics --example breakable_bridge`

use tumble_physics::{BodyDef, BodyKind, Event, JointDef, ShapeDef, StepSettings, World};

fn main() {
    let mut world = World::new(StepSettings::default());
    let post = |world: &mut World, x: f32| {
        world
            .create_body(
                &BodyDef::new(ShapeDef::Box {
                    half_extents: [0.2, 0.2],
                    radius: 0.0,
                })
                .kind(BodyKind::Static)
                .at(x, 5.0),
            )
            .expect("post")
    };
    // Ten planks of 1 m (0.5 kg each) hinged end to end between two posts 9 m apart, laid
    // in a V that sags 2.2 m (each half at acos(0.9) below level), so the chain is slack.
    let slope = 0.9f32.acos();
    let corner = |k: usize| {
        let down = k.min(10 - k) as f32;
        (-4.5 + k as f32 * slope.cos(), 5.0 - down * slope.sin())
    };
    let mut left = post(&mut world, -4.5);
    let mut hinges = Vec::new();
    for k in 0..10 {
        let ((x0, y0), (x1, y1)) = (corner(k), corner(k + 1));
        let plank = world
            .create_body(
                &BodyDef::new(ShapeDef::Box {
                    half_extents: [0.5, 0.05],
                    radius: 0.0,
                })
                .density(5.0)
                .at(0.5 * (x0 + x1), 0.5 * (y0 + y1))
                .angle((y1 - y0).atan2(x1 - x0)),
            )
            .expect("plank");
        let hinge = JointDef::hinge([left, plank], [x0, y0]);
        hinges.push(world.create_joint(&hinge).expect("hinge"));
        left = plank;
    }
    let right = post(&mut world, 4.5);
    let last = JointDef::hinge([left, right], [4.5, 5.0]);
    hinges.push(world.create_joint(&last).expect("hinge"));

    // The bridge settles under its own weight (a straight chain pulls hard at first, then
    // sags): the most any hinge pulls over its last second, at rest, sets the threshold, at
    // three times that.
    let mut most = 0.0f32;
    for step in 0..240 {
        world.step(1.0 / 60.0, 4);
        if step >= 180 {
            for &h in &hinges {
                most = most.max(world.joint_reaction(h).expect("hinge").0.length());
            }
        }
    }
    let threshold = 3.0 * most;
    for &h in &hinges {
        world
            .set_joint_thresholds(h, threshold, f32::INFINITY)
            .expect("threshold");
    }
    let sag = world
        .body(tumble_physics::BodyId::scene(6))
        .expect("middle")
        .position
        .y;
    println!(
        "settled: the middle plank at y = {sag:.2} m, hinges pull at most {most:.0} N; each breaks past {threshold:.0} N"
    );
    let mut broken = 0;

    // A 200 kg crate dropped on the middle: the hinges near it pass the threshold and break.
    let crate_ = world
        .create_body(
            &BodyDef::new(ShapeDef::Box {
                half_extents: [0.5, 0.5],
                radius: 0.0,
            })
            .density(200.0)
            .at(0.0, 7.0),
        )
        .expect("crate");
    for step in 1..=180 {
        world.step(1.0 / 60.0, 4);
        for event in world.events().to_vec() {
            if let Event::JointThreshold { joint, force, .. } = event {
                println!(
                    "step {step}: hinge {} pulls {force:.0} N: it breaks",
                    joint.index
                );
                world.destroy_joint(joint).expect("a live hinge");
                broken += 1;
            }
        }
    }
    println!("{broken} of {} hinges broke", hinges.len());
    // A chain's tension is nearly the same along it: the blow of the landing passes every
    // threshold at once, and the crate falls through.
    assert!(broken >= 1, "the crate should break the bridge");
    let y = world.body(crate_).expect("crate").position.y;
    println!("the crate fell to y = {y:.2} m");
    assert!(y < 0.0, "{y}");
    assert_eq!(world.joint_count(), hinges.len() - broken);
}
