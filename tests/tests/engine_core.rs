//! The engine core at scene level (issue 15): bodies of several shapes, filters, ids and
//! run-time changes, islands and sleeping. Every test calls `World::validate` after each
//! change and step, so an invariant broken between the stores fails where it breaks.

use glam::Vec2;
use tumble_physics::{
    BodyDef, BodyId, BodyKind, Filter, Limits, PartDef, SceneDef, ShapeDef, StepSettings,
    WideThresholds, World, WorldError,
};

const DT: f32 = 1.0 / 60.0;

fn step_checked(w: &mut World, steps: usize) {
    for _ in 0..steps {
        w.step(DT, 4);
        if let Err(e) = w.validate() {
            panic!("after step {}: {e}", w.step_count());
        }
    }
    assert_eq!(w.non_finite_bodies(), 0);
}

fn ground() -> BodyDef {
    BodyDef::new(ShapeDef::Box {
        half_extents: [20.0, 0.5],
        radius: 0.0,
    })
    .kind(BodyKind::Static)
    .at(0.0, -0.5)
}

fn disc(r: f32) -> PartDef {
    PartDef::new(ShapeDef::Circle { radius: r })
}

/// A dumbbell: two discs of radius 0.25 at x = ±1 in the body's frame, its origin at `x, y`.
fn dumbbell(x: f32, y: f32) -> BodyDef {
    BodyDef::compound(vec![
        disc(0.25).at(-1.0, 0.0, 0.0),
        disc(0.25).at(1.0, 0.0, 0.0),
    ])
    .at(x, y)
}

#[test]
fn a_body_of_two_shapes_rests_on_both_and_has_their_mass() {
    let mut scene = SceneDef::new("dumbbell");
    scene.push(ground());
    scene.push(dumbbell(0.0, 2.0));
    let mut w = World::from_scene(&scene, &Limits::default()).unwrap();
    // Mass: two discs of π·0.25² at density 1 (f32 sums: 1e-6 relative).
    let m = 2.0 * std::f32::consts::PI * 0.0625;
    assert!(
        (w.mass(BodyId::scene(1)).unwrap() / m - 1.0).abs() < 1e-6,
        "{}",
        w.mass(BodyId::scene(1)).unwrap()
    );
    // Parallel axis: 2·(m₁r²/2 + m₁·1²).
    let i = 2.0 * (0.5 * (m / 2.0) * 0.0625 + m / 2.0);
    assert!(
        (w.inertia(BodyId::scene(1)).unwrap() / i - 1.0).abs() < 1e-5,
        "{}",
        w.inertia(BodyId::scene(1)).unwrap()
    );
    w.settings_mut().enable_sleep = false;
    step_checked(&mut w, 180);
    let b = w.body(BodyId::scene(1)).unwrap();
    // Both discs rest on the ground: the centre 0.25 m up (within the contact's soft
    // overlap, a slop of 5 mm), level, and the frame's origin where the centre is.
    assert!((b.position.y - 0.25).abs() < 0.005, "{:?}", b.position);
    assert!(b.angle.abs() < 1e-3, "{}", b.angle);
    assert!((b.origin - b.position).length() < 1e-6);
    // Two contacts, one per disc.
    let touching = w.contacts().filter(|c| c.manifold.count > 0).count();
    assert_eq!(touching, 2);
}

#[test]
fn an_off_centre_part_moves_the_centre_of_mass_and_the_body_turns_about_it() {
    // A big disc and a small one off to the side: the centre is between them, nearer the big
    // one; the frame's origin stays where the scene put it until the body moves.
    let body = BodyDef::compound(vec![disc(0.5), disc(0.25).at(1.0, 0.0, 0.0)]).at(3.0, 5.0);
    let mut scene = SceneDef::new("lopsided");
    scene.gravity = [0.0, 0.0];
    scene.push(body.spin(1.0));
    let mut w = World::from_scene(&scene, &Limits::default()).unwrap();
    let (m1, m2) = (0.25f32, 0.0625f32);
    let cx = m2 / (m1 + m2);
    assert!((w.local_center(BodyId::scene(0)).unwrap().x - cx).abs() < 1e-6);
    assert_eq!(
        w.body(BodyId::scene(0)).unwrap().origin,
        Vec2::new(3.0, 5.0)
    );
    // Spinning freely, the centre stays put and the origin circles it at radius cx.
    step_checked(&mut w, 90);
    let b = w.body(BodyId::scene(0)).unwrap();
    assert!((b.position - Vec2::new(3.0 + cx, 5.0)).length() < 1e-5);
    assert!(((b.origin - b.position).length() - cx).abs() < 1e-5);
}

#[test]
fn filters_decide_which_shapes_touch() {
    // Box2D's rule: categories against masks, overridden by a shared non-zero group.
    let a = Filter {
        category: 0b01,
        mask: 0b01,
        group: 0,
    };
    let b = Filter {
        category: 0b10,
        mask: u64::MAX,
        group: 0,
    };
    assert!(!a.should_collide(&b) && !b.should_collide(&a));
    let never = |f: Filter| Filter { group: -3, ..f };
    assert!(!never(Filter::default()).should_collide(&never(Filter::default())));
    let always = |f: Filter| Filter { group: 2, ..f };
    assert!(always(a).should_collide(&always(b)));
    // In a world: a ball whose mask leaves out the ground's category falls through it; a
    // ball of the ground's category rests on it.
    let mut scene = SceneDef::new("filters");
    scene.sleep = false;
    scene.push(ground().filter(Filter {
        category: 0b100,
        ..Filter::default()
    }));
    let ball = |x: f32| BodyDef::new(ShapeDef::Circle { radius: 0.5 }).at(x, 1.0);
    scene.push(ball(-2.0).filter(Filter {
        mask: !0b100,
        ..Filter::default()
    }));
    scene.push(ball(2.0));
    let mut w = World::from_scene(&scene, &Limits::default()).unwrap();
    step_checked(&mut w, 120);
    assert!(
        w.body(BodyId::scene(1)).unwrap().position.y < -5.0,
        "{:?}",
        w.body(BodyId::scene(1)).unwrap().position
    );
    assert!(
        (w.body(BodyId::scene(2)).unwrap().position.y - 0.5).abs() < 0.01,
        "{:?}",
        w.body(BodyId::scene(2)).unwrap().position
    );
}

#[test]
fn shapes_of_one_body_never_touch() {
    // Two overlapping parts of one body: no contact between them, so it just falls.
    let body = BodyDef::compound(vec![disc(0.5), disc(0.5).at(0.3, 0.0, 0.0)]).at(0.0, 10.0);
    let mut w = World::new(StepSettings::default());
    w.create_body(&body).unwrap();
    step_checked(&mut w, 30);
    assert_eq!(w.contact_count(), 0);
    let v = w.body(BodyId::scene(0)).unwrap().linear_velocity;
    assert!((v.y + 10.0 * 30.0 * DT).abs() < 1e-3, "{v:?}");
}

/// A 20-row pyramid of unit boxes on the ground, sleeping on.
fn pyramid(rows: usize) -> World {
    let mut w = World::new(StepSettings::default());
    w.create_body(&ground()).unwrap();
    for row in 0..rows {
        for col in 0..rows - row {
            let x = col as f32 + 0.5 * row as f32 - 0.5 * rows as f32;
            let b = BodyDef::new(ShapeDef::Box {
                half_extents: [0.5, 0.5],
                radius: 0.0,
            })
            .at(x, 0.5 + row as f32);
            w.create_body(&b).unwrap();
        }
    }
    w
}

#[test]
fn a_resting_pyramid_falls_asleep_as_one_island_and_then_costs_nothing() {
    let mut w = pyramid(20);
    let bodies = w.body_count() - 1;
    step_checked(&mut w, 1);
    // Touching contacts join every box into one island.
    assert_eq!(w.island_counts().0, 1);
    let mut asleep_at = None;
    for s in 0..600 {
        step_checked(&mut w, 1);
        if w.awake_body_count() == 0 {
            asleep_at = Some(s);
            break;
        }
    }
    // Box2D's time to sleep is 0.5 s (30 steps) once every box rests.
    let asleep_at = asleep_at.expect("the pyramid never fell asleep");
    assert!(asleep_at >= 29, "asleep after {asleep_at} steps");
    assert_eq!(w.island_counts(), (1, 0));
    let hash = w.state_hash();
    step_checked(&mut w, 60);
    // Asleep: nothing moves, nothing is solved, nothing is collided or moved in the tree.
    assert_eq!(w.state_hash(), hash);
    let p = w.profile();
    assert_eq!((p.touching, p.moved, p.recycled), (0, 0, 0));
    assert!(
        w.contact_count() >= bodies,
        "contacts are kept while asleep"
    );
}

#[test]
fn switching_sleep_off_wakes_every_island() {
    let mut w = pyramid(5);
    step_checked(&mut w, 200);
    assert_eq!(w.awake_body_count(), 0);
    w.settings_mut().enable_sleep = false;
    step_checked(&mut w, 1);
    assert_eq!(w.awake_body_count(), w.body_count() - 1);
    assert_eq!(w.island_counts(), (1, 1));
    step_checked(&mut w, 200);
    assert_eq!(w.awake_body_count(), w.body_count() - 1);
}

#[test]
fn a_ball_dropped_on_a_sleeping_pyramid_wakes_it() {
    let mut w = pyramid(10);
    step_checked(&mut w, 240);
    assert_eq!(w.awake_body_count(), 0);
    let ball = w
        .create_body(&BodyDef::new(ShapeDef::Circle { radius: 0.5 }).at(0.0, 14.0))
        .unwrap();
    step_checked(&mut w, 1);
    // The new ball is awake; the pyramid still sleeps until the ball touches it.
    assert_eq!(w.awake_body_count(), 1);
    assert!(w.body(ball).unwrap().awake);
    // It lands after about 1.5 s; the pyramid wakes (and may settle and sleep again).
    let mut most = 0;
    for _ in 0..150 {
        step_checked(&mut w, 1);
        most = most.max(w.awake_body_count());
    }
    assert_eq!(most, w.body_count() - 1, "only {most} bodies woke");
}

#[test]
fn a_sleeping_pile_beside_an_awake_body_is_not_walked() {
    // Issue 15: a sleeping body costs nothing while others are awake (Box2D's solver sets:
    // the stages walk the awake set only). The profile counts what the stages walked.
    let mut w = pyramid(10);
    let boxes = w.body_count() - 1;
    step_checked(&mut w, 240);
    assert_eq!(w.awake_body_count(), 0);
    let contacts = w.contact_count();
    // A ball falling for ever, far from the pile: one awake island beside a sleeping one.
    let far = BodyDef::new(ShapeDef::Circle { radius: 0.5 }).at(500.0, 0.0);
    w.create_body(&far).unwrap();
    let poses = |w: &World| {
        (1..=boxes)
            .map(|i| w.body(BodyId::scene(i)).unwrap())
            .collect::<Vec<_>>()
    };
    let asleep = poses(&w);
    for _ in 0..30 {
        step_checked(&mut w, 1);
        let p = *w.profile();
        assert_eq!((p.moving, p.collided, p.touching), (1, 0, 0));
    }
    assert_eq!(poses(&w), asleep, "a sleeping box moved");
    assert_eq!(w.contact_count(), contacts);
    // A box lands on the pile's top box and wakes it: then every contact is walked.
    let on_top = BodyDef::new(ShapeDef::Box {
        half_extents: [0.4, 0.4],
        radius: 0.0,
    })
    .at(-0.5, 11.0);
    w.create_body(&on_top).unwrap();
    let mut woke = false;
    for _ in 0..120 {
        // The pile wakes after the narrow phase of the step the ball touches it; from the
        // next step on, it is walked.
        let was_awake = w.awake_body_count() > 2;
        step_checked(&mut w, 1);
        let p = *w.profile();
        if was_awake && w.awake_body_count() > 2 {
            woke = true;
            assert_eq!(p.moving, w.awake_body_count());
            // Every contact walked (those that parted in the step are gone from the count).
            assert!(p.collided >= w.contact_count(), "{} walked", p.collided);
        }
    }
    assert!(woke, "the box never woke the pile");
    // The pile (and the box on it) fall asleep again; the far ball falls on, alone.
    step_checked(&mut w, 240);
    assert_eq!(w.awake_body_count(), 1);
    step_checked(&mut w, 1);
    let p = *w.profile();
    assert_eq!((p.moving, p.collided), (1, 0));
}

#[test]
fn ids_are_refused_once_their_body_is_gone() {
    let mut w = pyramid(3);
    let top = BodyId::scene(w.body_count() - 1);
    step_checked(&mut w, 10);
    w.destroy_body(top).unwrap();
    w.validate().unwrap();
    assert_eq!(w.body(top), Err(WorldError::NoBody(top)));
    assert_eq!(w.destroy_body(top), Err(WorldError::NoBody(top)));
    // The next body takes the slot under a new generation: the old id still names nothing.
    let new = w
        .create_body(&BodyDef::new(ShapeDef::Circle { radius: 0.2 }).at(0.0, 8.0))
        .unwrap();
    assert_eq!(new.index, top.index);
    assert_ne!(new.generation, top.generation);
    assert!(w.body(top).is_err() && w.body(new).is_ok());
    step_checked(&mut w, 60);
}

#[test]
fn destroying_the_ground_wakes_what_rests_on_it_and_it_falls() {
    let mut w = pyramid(4);
    step_checked(&mut w, 240);
    assert_eq!(w.awake_body_count(), 0);
    w.destroy_body(BodyId::scene(0)).unwrap();
    w.validate().unwrap();
    assert_eq!(w.awake_body_count(), w.body_count());
    step_checked(&mut w, 60);
    assert!(
        w.body(BodyId::scene(1)).unwrap().position.y < -3.0,
        "{:?}",
        w.body(BodyId::scene(1)).unwrap().position
    );
}

#[test]
fn moving_the_ground_wakes_what_sleeps_on_it() {
    let mut w = pyramid(4);
    step_checked(&mut w, 240);
    assert_eq!(w.awake_body_count(), 0);
    w.set_transform(BodyId::scene(0), Vec2::new(0.0, -3.0), 0.0)
        .unwrap();
    assert_eq!(w.awake_body_count(), w.body_count() - 1);
    step_checked(&mut w, 30);
    assert!(
        w.body(BodyId::scene(1)).unwrap().position.y < 0.0,
        "{:?}",
        w.body(BodyId::scene(1)).unwrap().position
    );
}

#[test]
fn run_time_changes_keep_every_store_consistent() {
    let mut w = pyramid(5);
    step_checked(&mut w, 30);
    let id = |_: &World, i: usize| BodyId::scene(i);
    // A shape added to a box: it gets heavier and its contacts' masses follow.
    let b = id(&w, 3);
    let m0 = w.mass(BodyId::scene(3)).unwrap();
    let s = w.create_shape(b, &disc(0.3).at(0.0, 0.6, 0.0)).unwrap();
    w.validate().unwrap();
    assert!(w.mass(BodyId::scene(3)).unwrap() > m0);
    step_checked(&mut w, 10);
    w.destroy_shape(s).unwrap();
    w.validate().unwrap();
    assert_eq!(w.mass(BodyId::scene(3)).unwrap(), m0);
    assert!(w.destroy_shape(s).is_err());
    // The last shape of a dynamic body cannot go.
    let only = w.body_shapes(BodyId::scene(3)).unwrap().next().unwrap().id;
    assert!(w.destroy_shape(only).is_err());
    // Kinds: a box made static, one made kinematic and moved, one teleported.
    w.set_kind(id(&w, 1), BodyKind::Static).unwrap();
    w.validate().unwrap();
    w.set_kind(id(&w, 2), BodyKind::Kinematic).unwrap();
    w.set_velocity(id(&w, 2), Vec2::new(0.5, 0.0), 0.0).unwrap();
    w.validate().unwrap();
    w.set_transform(id(&w, 4), Vec2::new(0.0, 9.0), 0.3)
        .unwrap();
    w.validate().unwrap();
    step_checked(&mut w, 60);
    // And back to dynamic.
    w.set_kind(id(&w, 1), BodyKind::Dynamic).unwrap();
    w.set_kind(id(&w, 2), BodyKind::Dynamic).unwrap();
    w.validate().unwrap();
    step_checked(&mut w, 240);
    // Bad input is refused without a change.
    let hash = w.state_hash();
    assert!(
        w.set_transform(id(&w, 4), Vec2::new(f32::NAN, 0.0), 0.0)
            .is_err()
    );
    assert!(w.set_velocity(id(&w, 4), Vec2::INFINITY, 0.0).is_err());
    assert!(
        w.create_body(&BodyDef::new(ShapeDef::Circle { radius: -1.0 }))
            .is_err()
    );
    assert_eq!(w.state_hash(), hash);
}

/// Builds a scene, runs it on `threads` with every stage split, and returns its hash, after
/// checking the stores after every step.
fn run_split(scene: &SceneDef, threads: usize, steps: usize) -> u64 {
    let mut w = World::from_scene(scene, &Limits::default()).unwrap();
    w.set_workers_beyond_cores(true);
    w.set_wide_thresholds(WideThresholds::ALWAYS);
    w.set_thread_count(threads);
    let script = tumble_scene::builtin::script(&scene.name);
    for _ in 0..steps {
        if let Some(script) = script {
            script(w.step_count(), &mut w);
        }
        w.step(scene.dt, scene.substeps);
    }
    w.validate().unwrap();
    assert_eq!(w.non_finite_bodies(), 0);
    w.state_hash()
}

#[test]
fn sleeping_and_waking_are_the_same_on_any_thread_count() {
    // A small smash: a block into a wall of boxes that start asleep, waking as it is hit.
    let mut scene = SceneDef::new("small_smash");
    scene.gravity = [0.0, 0.0];
    scene.push(
        BodyDef::new(ShapeDef::Box {
            half_extents: [1.0, 1.0],
            radius: 0.0,
        })
        .at(-5.0, 0.0)
        .velocity(20.0, 0.0)
        .density(8.0),
    );
    for i in 0..20 {
        for j in 0..20 {
            let b = BodyDef::new(ShapeDef::Box {
                half_extents: [0.2, 0.2],
                radius: 0.0,
            })
            .at(i as f32 * 0.4, (j as f32 - 10.0) * 0.4)
            .awake(false);
            scene.push(b);
        }
    }
    let one = run_split(&scene, 1, 150);
    assert_eq!(run_split(&scene, 2, 150), one);
    assert_eq!(run_split(&scene, 3, 150), one);
    // Compound bodies: a few dozen dumbbells piling up and falling asleep.
    let mut pile = SceneDef::new("dumbbells");
    pile.push(ground());
    for k in 0..40 {
        pile.push(dumbbell((k % 5) as f32 * 2.5 - 5.0, 1.0 + (k / 5) as f32 * 0.8).spin(0.3));
    }
    let one = run_split(&pile, 1, 300);
    assert_eq!(run_split(&pile, 2, 300), one);
    assert_eq!(run_split(&pile, 4, 300), one);
}

#[test]
fn a_snapshot_taken_while_islands_sleep_and_wake_continues_bit_for_bit() {
    let mut w = pyramid(6);
    step_checked(&mut w, 200);
    assert_eq!(w.awake_body_count(), 0);
    w.create_body(&BodyDef::new(ShapeDef::Circle { radius: 0.4 }).at(0.3, 12.0))
        .unwrap();
    step_checked(&mut w, 40);
    let text = serde_json_snapshot(&w);
    let mut restored = World::from_snapshot(serde_json_restore(&text)).unwrap();
    restored.validate().unwrap();
    for _ in 0..200 {
        w.step(DT, 4);
        restored.step(DT, 4);
    }
    assert_eq!(w.state_hash(), restored.state_hash());
    assert_eq!(w.awake_body_count(), restored.awake_body_count());
    assert_eq!(w.island_counts(), restored.island_counts());
}

fn serde_json_snapshot(w: &World) -> String {
    serde_json::to_string(&w.snapshot()).unwrap()
}

fn serde_json_restore(text: &str) -> tumble_physics::WorldSnapshot {
    serde_json::from_str(text).unwrap()
}

#[test]
fn the_benchmark_scenes_of_several_shapes_load_and_stay_consistent() {
    for name in ["compounds", "junkyard", "smash"] {
        let scene = tumble_scene::builtin::build(name).unwrap();
        let mut w = World::from_scene(&scene, &Limits::default()).unwrap();
        w.validate().unwrap();
        let script = tumble_scene::builtin::script(name);
        for _ in 0..20 {
            if let Some(script) = script {
                script(w.step_count(), &mut w);
            }
            w.step(scene.dt, scene.substeps);
        }
        w.validate().unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(w.non_finite_bodies(), 0, "{name}");
    }
    // smash's grid starts asleep: only the block is awake.
    let smash = tumble_scene::builtin::build("smash").unwrap();
    let w = World::from_scene(&smash, &Limits::default()).unwrap();
    assert_eq!(w.awake_body_count(), 1);
    // compounds: 3000 bodies of two shapes and one static body of 282.
    let compounds = tumble_scene::builtin::build("compounds").unwrap();
    let w = World::from_scene(&compounds, &Limits::default()).unwrap();
    assert_eq!(w.body_count(), 3001);
    assert_eq!(w.shapes().count(), 6000 + 282);
}

/// A column of `n` boxes 1 m tall with 0.3 m between them, falling freely together.
fn falling_column(n: usize, bullet: bool) -> World {
    let mut scene = SceneDef::new("column");
    for k in 0..n {
        let unit = ShapeDef::Box {
            half_extents: [0.5, 0.5],
            radius: 0.0,
        };
        scene.push(BodyDef::new(unit).at(0.0, 1.3 * k as f32).bullet(bullet));
    }
    scene.sleep = false;
    World::from_scene(&scene, &Limits::default()).unwrap()
}

#[test]
fn bodies_falling_together_make_no_pairs_unless_they_are_bullets() {
    // After 2 s of free fall (20 m/s, 0.33 m a step) each box's box swept along its motion
    // reaches the one below (0.3 m away), but their unswept fat boxes (0.07 m of speculative
    // distance and margin each) never meet: two moving bodies pair by those (Box2D's rule),
    // so the column has no contact. Bullets pair by their swept boxes, as every body does
    // with a static one: the same column of bullets has a contact between each neighbour.
    let mut plain = falling_column(10, false);
    let mut bullets = falling_column(10, true);
    step_checked(&mut plain, 120);
    step_checked(&mut bullets, 120);
    assert_eq!(plain.contact_count(), 0);
    assert_eq!(bullets.contact_count(), 9);
    // Nothing touched: both fell the same way, bit for bit.
    for i in 0..10 {
        assert_eq!(
            plain.body(BodyId::scene(i)).unwrap().position,
            bullets.body(BodyId::scene(i)).unwrap().position
        );
    }
    // Making the bullets plain again drops those pairs at the next narrow phase.
    for i in 0..10 {
        bullets.set_bullet(BodyId::scene(i), false).unwrap();
        bullets.validate().unwrap();
    }
    step_checked(&mut bullets, 1);
    assert_eq!(bullets.contact_count(), 0);
}

/// Two discs of radius 0.25 flying at each other at `speed` each, without gravity: the
/// deepest overlap they reach (m) and whether they passed through each other.
fn head_on(speed: f32, bullet: bool) -> (f32, bool) {
    let mut scene = SceneDef::new("head_on");
    scene.gravity = [0.0, 0.0];
    let disc = ShapeDef::Circle { radius: 0.25 };
    scene.push(
        BodyDef::new(disc.clone())
            .at(-5.0, 0.0)
            .velocity(speed, 0.0)
            .bullet(bullet),
    );
    scene.push(BodyDef::new(disc).at(5.0, 0.0).velocity(-speed, 0.0));
    let mut w = World::from_scene(&scene, &Limits::default()).unwrap();
    let mut deepest = 0.0f32;
    for _ in 0..120 {
        step_checked(&mut w, 1);
        let gap = (w.body(BodyId::scene(1)).unwrap().position
            - w.body(BodyId::scene(0)).unwrap().position)
            .length()
            - 0.5;
        deepest = deepest.max(-gap);
    }
    (
        deepest,
        w.body(BodyId::scene(0)).unwrap().position.x > w.body(BodyId::scene(1)).unwrap().position.x,
    )
}

#[test]
fn a_bullet_meets_a_fast_body_where_they_touch() {
    // 120 m/s closing is 2 m a step, four diameters. Plain bodies pair when their unswept
    // fat boxes meet, which these skip over: they pass through each other (Box2D without
    // bullets does the same). A bullet pairs a step early by its swept box and its
    // speculative contact stops both where they touch: measured overlap 0; 5 mm is the
    // linear slop the soft contact may leave.
    let (plain, passed) = head_on(60.0, false);
    assert!(passed, "plain discs met (overlap {plain} m)");
    let (bullet, passed) = head_on(60.0, true);
    assert!(!passed, "the bullet passed through");
    assert!(bullet <= 0.005, "the bullet overlapped by {bullet} m");
}
