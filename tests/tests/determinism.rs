//! Determinism across thread counts: the same scene stepped on 1, 2, 3 and 4 threads, and with
//! the thread count changed mid-run, ends in bit-identical states.

use tumble_physics::{
    BodyDef, BodyId, BodyKind, Event, EventCursor, JointDef, PartDef, SceneDef, ShapeDef,
    StepSettings, WideThresholds, World,
};
use tumble_tests::{all_finite, world};

const STEPS: u32 = 240;

/// Every body's state as raw bits: position x, y, rotation cos, sin, velocity x, y, angular.
fn snapshot(w: &World) -> Vec<[u32; 7]> {
    w.bodies()
        .map(|(_, b)| {
            [
                b.position.x.to_bits(),
                b.position.y.to_bits(),
                b.rotation.c.to_bits(),
                b.rotation.s.to_bits(),
                b.linear_velocity.x.to_bits(),
                b.linear_velocity.y.to_bits(),
                b.angular_velocity.to_bits(),
            ]
        })
        .collect()
}

struct Run {
    label: String,
    state: Vec<[u32; 7]>,
    hash: u64,
    contacts: usize,
    /// Touching contacts (manifold points > 0) that involve a circle.
    circle_contacts: usize,
    /// Every event of the run, with the world's step count when it was read.
    events: Vec<(u64, Event)>,
    /// Bodies continuous collision moved back to their time of impact, over the run.
    rewound: usize,
}

impl Run {
    /// What a run ends in: `w`'s state bits, hash and contact count, and the events `log`
    /// read.
    fn of(label: String, w: &World, circle_contacts: usize, log: EventLog) -> Run {
        Run {
            label,
            state: snapshot(w),
            hash: w.state_hash(),
            contacts: w.contact_count(),
            circle_contacts,
            events: log.events,
            rewound: log.rewound,
        }
    }
}

/// The events of a run, read after each step and after each change between steps (the
/// world's list holds the last step's events and those made since).
#[derive(Default)]
struct EventLog {
    events: Vec<(u64, Event)>,
    /// What of the world's events is read.
    cursor: EventCursor,
    /// Bodies continuous collision moved back, summed over the steps read.
    rewound: usize,
}

impl EventLog {
    /// Reads what the world made since the last read; `stepped`: a step ran since (its
    /// profile is counted).
    fn read(&mut self, w: &World, stepped: bool) {
        if stepped {
            self.rewound += w.profile().rewound;
        }
        let new = self.cursor.take(w);
        self.events.extend(new.iter().map(|e| (w.step_count(), *e)));
    }
}

/// Thresholds that `falling_circles` crosses while it runs (measured: its contacts grow from
/// 330 to about 720 and its touching ones from 330 to about 580 as the circles land, with
/// 150 to 180 proxies moving each step): its first ~75 steps run inline (contacts and moved
/// below 600), then the step goes wide, and the narrow phase, prepare and the solver split
/// from about step 90 on (contacts above 500, touching above 460 and 400). The defaults
/// keep this 300-body scene inline.
const CROSSING: WideThresholds = WideThresholds {
    step: 300,
    broad_phase: 60,
    narrow_phase: 250,
    prepare: 230,
    solve: 200,
    finalize: 140,
    solve_by_payoff: false,
};

/// Runs `falling_circles` for 240 steps, 4 s: the 180 circles start 18 m to 35 m up, the
/// lowest reach the 15 m top of the pyramid after about 0.7 s and the highest the ground by
/// about 2.6 s, then bounce and roll among its 120 boxes. The thread count for each step is
/// `threads(step)`; stages split by [`CROSSING`].
fn run(label: &str, threads: impl Fn(u32) -> usize) -> Run {
    run_with(label, threads, CROSSING, |_| {})
}

/// [`run`] with the stage thresholds `wide` and the step settings changed by `tweak` first.
fn run_with(
    label: &str,
    threads: impl Fn(u32) -> usize,
    wide: WideThresholds,
    tweak: impl Fn(&mut StepSettings),
) -> Run {
    let scene = match tumble_scene::builtin::build("falling_circles") {
        Some(s) => s,
        None => panic!("no built-in falling_circles"),
    };
    let first_circle = scene
        .bodies
        .iter()
        .position(|b| matches!(b.shape, Some(ShapeDef::Circle { .. })))
        .unwrap_or(scene.bodies.len());
    let t0 = std::time::Instant::now();
    let mut w = world(&scene);
    w.set_wide_thresholds(wide);
    tweak(w.settings_mut());
    let cores = tumble_physics::default_thread_count();
    let (mut inline_steps, mut parallel_solves) = (0, 0);
    let mut log = EventLog::default();
    for step in 0..STEPS {
        let n = threads(step);
        w.set_thread_count(n);
        w.step(scene.dt, scene.substeps);
        log.read(&w, true);
        // The solver must really run on several workers whenever it may: in a step that left
        // the caller's thread, with two workers' worth of touching contacts, on as many
        // workers as there are threads and cores.
        let p = w.profile();
        if p.inline {
            inline_steps += 1;
            assert_eq!(p.solver_workers, 1, "{label}: step {step} ran inline");
        } else if p.touching >= 2 * wide.solve {
            assert_eq!(p.solver_workers, n.min(cores), "{label}: step {step}");
            parallel_solves += usize::from(p.solver_workers > 1);
        }
    }
    if wide == WideThresholds::default() {
        assert_eq!(
            inline_steps, STEPS,
            "{label}: a small scene left the caller's thread"
        );
    } else if cores > 1 && threads(STEPS - 1) > 1 {
        assert!(
            parallel_solves > 0,
            "{label}: the parallel solver never ran"
        );
    }
    // Thresholds that this scene crosses: some steps inline, some not.
    if wide == CROSSING && threads(0) > 1 && threads(STEPS - 1) > 1 {
        assert!(
            inline_steps > 0 && inline_steps < STEPS,
            "{label}: {inline_steps} of {STEPS} steps inline; the thresholds are not crossed"
        );
    }
    assert!(all_finite(&w), "{label}: non-finite state");
    let circle_contacts = w
        .contacts()
        .filter(|c| {
            c.manifold.count > 0 && c.body_a.index.max(c.body_b.index) as usize >= first_circle
        })
        .count();
    eprintln!(
        "{label}: {} contacts, {circle_contacts} touching a circle, hash {:016x}, {:.0} ms",
        w.contact_count(),
        w.state_hash(),
        t0.elapsed().as_secs_f64() * 1e3
    );
    Run::of(label.to_string(), &w, circle_contacts, log)
}

const FIELDS: [&str; 7] = ["x", "y", "cos", "sin", "vx", "vy", "w"];

fn assert_same(reference: &Run, other: &Run) {
    assert_eq!(reference.state.len(), other.state.len());
    for (i, (a, b)) in reference.state.iter().zip(&other.state).enumerate() {
        for k in 0..7 {
            assert!(
                a[k] == b[k],
                "body {i} {}: {} ({}) vs {} ({}): bits differ",
                FIELDS[k],
                f32::from_bits(a[k]),
                reference.label,
                f32::from_bits(b[k]),
                other.label
            );
        }
    }
    assert_eq!(
        reference.hash, other.hash,
        "state_hash {} vs {}",
        reference.label, other.label
    );
    assert_eq!(
        reference.contacts, other.contacts,
        "contact count {} vs {}",
        reference.label, other.label
    );
    assert_eq!(
        reference.rewound, other.rewound,
        "bodies moved back by continuous collision {} vs {}",
        reference.label, other.label
    );
    assert_eq!(
        reference.events.len(),
        other.events.len(),
        "event count {} vs {}",
        reference.label,
        other.label
    );
    for (a, b) in reference.events.iter().zip(&other.events) {
        assert!(
            a == b,
            "events differ: {a:?} ({}) vs {b:?} ({})",
            reference.label,
            other.label
        );
    }
}

#[test]
fn falling_circles_is_bit_identical_on_any_thread_count() {
    let one = run("1 thread", |_| 1);
    // The scene must exercise the contact solver, or the comparison says little: by step 240
    // the circles lie on and around the pyramid, touching it, the ground and each other. Each
    // resting circle has a support contact of its own (a circle-circle contact supports only
    // the upper one), so 180 resting circles make at least 180 (measured: 281 of 713).
    assert!(
        one.circle_contacts >= 180,
        "falling_circles has only {} touching contacts with circles after {STEPS} steps ({} in all)",
        one.circle_contacts,
        one.contacts
    );
    for n in [2, 3, 4] {
        assert_same(&one, &run(&format!("{n} threads"), |_| n));
    }
    // Every stage split whatever its size, and none ever (the defaults keep this scene inline,
    // the path a small scene takes on any thread count).
    for (wide, name) in [
        (WideThresholds::ALWAYS, "every stage split"),
        (WideThresholds::default(), "default thresholds"),
    ] {
        for n in [2, 4] {
            let label = format!("{n} threads, {name}");
            assert_same(&one, &run_with(&label, |_| n, wide, |_| {}));
        }
    }
    // Thread count changed every 10 steps: 1, 2, 3, 4, 1, 2, ...
    let switching = run("switching 1-4 every 10 steps", |step| {
        (step / 10 % 4) as usize + 1
    });
    assert_same(&one, &switching);
}

#[test]
fn a_repeated_run_gives_the_same_hash() {
    // Two threads: parallel, and as many as the 2-core machines the suite runs on have.
    let a = run("2 threads, first run", |_| 2);
    let b = run("2 threads, second run", |_| 2);
    assert_same(&a, &b);
}

#[test]
fn repeated_restitution_passes_are_bit_identical_on_any_thread_count() {
    // The restitution passes run colour by colour on every worker, like the solve: 8 passes
    // at threshold 0 make every bounce of the circles (restitution 0.3) go through them.
    // Under Box2D's rule (`impacts_bounce` off), where the passes are exactly these.
    let bouncy = |s: &mut StepSettings| {
        s.impacts_bounce = false;
        s.restitution_threshold = 0.0;
        s.restitution_iterations = 8;
    };
    let one = run_with("8 restitution passes, 1 thread", |_| 1, CROSSING, bouncy);
    for n in [2, 3, 4] {
        assert_same(
            &one,
            &run_with(
                &format!("8 restitution passes, {n} threads"),
                |_| n,
                CROSSING,
                bouncy,
            ),
        );
    }
    // And they change the result: the passes really ran.
    let single = run_with(
        "1 restitution pass, 1 thread",
        |_| 1,
        CROSSING,
        |s| {
            s.impacts_bounce = false;
            s.restitution_threshold = 0.0;
        },
    );
    assert_ne!(one.hash, single.hash);
}

/// Steps `scene` for `steps` steps on `workers` real solver workers (beyond the cores where
/// the machine has fewer), checking each step that the solver ran on all of them; the state
/// bits, the largest overflow seen and the kinematic bodies' count.
fn run_workers(scene: &SceneDef, steps: u32, workers: usize) -> (Run, usize) {
    run_workers_with(scene, steps, workers, true)
}

/// [`run_workers`]; with `strict` off, a step the solver ran on fewer workers (too few
/// touching contacts to share: a grid still asleep) is allowed.
fn run_workers_with(scene: &SceneDef, steps: u32, workers: usize, strict: bool) -> (Run, usize) {
    run_workers_tweaked(scene, steps, workers, strict, |_| {})
}

/// [`run_workers_with`] with the step settings changed by `tweak` first.
fn run_workers_tweaked(
    scene: &SceneDef,
    steps: u32,
    workers: usize,
    strict: bool,
    tweak: impl Fn(&mut StepSettings),
) -> (Run, usize) {
    let mut w = world(scene);
    tweak(w.settings_mut());
    w.set_workers_beyond_cores(true);
    w.set_thread_count(workers);
    let mut overflow = 0;
    let mut log = EventLog::default();
    for step in 0..steps {
        w.step(scene.dt, scene.substeps);
        log.read(&w, true);
        let p = w.profile();
        assert!(
            !strict || p.solver_workers == workers,
            "{}: step {step} solved on {} workers, not {workers}",
            scene.name,
            p.solver_workers
        );
        overflow = overflow.max(p.overflow);
    }
    assert!(all_finite(&w), "{}: non-finite state", scene.name);
    (
        Run::of(format!("{} on {workers} workers", scene.name), &w, 0, log),
        overflow,
    )
}

/// `large_pyramid` with two more things beside it: 30 posts carrying one plank (the plank's
/// 30 contacts with dynamic bodies exceed the 20 colours such contacts may take, so 10 go to
/// the overflow, which one worker solves alone while the others wait), and a kinematic box
/// pushing the pyramid's left flank at 1 m/s from step 30 on.
fn pyramid_with_overflow_and_kinematic() -> SceneDef {
    let mut scene = tumble_scene::builtin::build("large_pyramid").expect("large_pyramid");
    let unit = ShapeDef::Box {
        half_extents: [0.5, 0.5],
        radius: 0.0,
    };
    for i in 0..30 {
        scene.push(BodyDef::new(unit.clone()).at(55.0 + 1.5 * i as f32, 0.5));
    }
    scene.push(
        BodyDef::new(ShapeDef::Box {
            half_extents: [23.0, 0.25],
            radius: 0.0,
        })
        .at(55.0 + 1.5 * 14.5, 1.25),
    );
    // The pusher carries a sensor disc of radius 3 into the pyramid (its visitors change
    // as it goes), and a static sensor box holds the pyramid's left third.
    scene.push(
        BodyDef::compound(vec![
            PartDef::new(unit),
            PartDef::new(ShapeDef::Circle { radius: 3.0 }).sensor(true),
        ])
        .kind(BodyKind::Kinematic)
        .at(-51.0, 0.5)
        .velocity(1.0, 0.0),
    );
    scene.push(
        BodyDef::compound(vec![
            PartDef::new(ShapeDef::Box {
                half_extents: [15.0, 20.0],
                radius: 0.0,
            })
            .sensor(true),
        ])
        .kind(BodyKind::Static)
        .at(-35.0, 20.0),
    );
    // Fast spinning capsules shot down at the ground beside the pyramid, and a bullet disc
    // into its right flank: continuous collision sweeps them while the pyramid is solved.
    for i in 0..3 {
        scene.push(
            BodyDef::new(ShapeDef::Capsule {
                center1: [-0.5, 0.0],
                center2: [0.5, 0.0],
                radius: 0.05,
            })
            .at(-70.0 - 4.0 * i as f32, 30.0)
            .velocity(0.0, -250.0)
            .spin(50.0),
        );
    }
    scene.push(
        BodyDef::new(ShapeDef::Circle { radius: 0.1 })
            .at(60.0, 3.0)
            .velocity(-300.0, 0.0)
            .bullet(true),
    );
    scene.name = "large_pyramid + plank + kinematic + sensors + fast bodies".into();
    scene
}

#[test]
fn benchmark_scenes_are_bit_identical_on_1_to_4_real_workers() {
    // 60 steps each (1 s). The solver runs 3 and 4 workers even on a 2-core machine (the
    // default caps them at the cores), so each colour's blocks are really shared four ways.
    let pyramid = pyramid_with_overflow_and_kinematic();
    // smash's ram starts 50 m from the grid and reaches it after 69 steps: moved to 10 m, it
    // hits at step 15, and the 60 steps cover the impact and contacts made and broken.
    // Sleeping off here, so that every step is solved by all the workers (the grid starts
    // asleep in the built-in; that case follows).
    let mut smash = tumble_scene::builtin::build("smash").expect("smash");
    smash.bodies[0].position = [16.0, 0.0];
    let asleep = smash.clone();
    smash.sleep = false;
    for scene in [&pyramid, &smash] {
        let (one, overflow) = run_workers(scene, 60, 1);
        if scene.name != "smash" {
            assert!(overflow >= 10, "{}: overflow {overflow}", scene.name);
            // Events of every kind the scene makes: the pyramid settling, the pusher's disc
            // entering it, the static sensor's visitors.
            let has = |f: fn(&Event) -> bool| one.events.iter().any(|(_, e)| f(e));
            assert!(has(|e| matches!(e, Event::ContactBegin { .. })));
            assert!(has(|e| matches!(e, Event::SensorBegin { .. })));
            assert!(has(|e| matches!(e, Event::SensorEnd { .. })));
            assert!(one.rewound >= 4, "swept bodies moved back: {}", one.rewound);
        } else {
            // The ram hits the grid at 15 m/s and knocks boxes apart.
            let has = |f: fn(&Event) -> bool| one.events.iter().any(|(_, e)| f(e));
            assert!(has(|e| matches!(e, Event::Hit { .. })), "smash: no hit");
            assert!(has(|e| matches!(e, Event::ContactEnd { .. })));
        }
        for workers in 2..=4 {
            let (other, _) = run_workers(scene, 60, workers);
            assert_same(&one, &other);
        }
    }
    // As Box2D builds it: the grid asleep, woken box by box as the ram goes in.
    let (one, _) = run_workers_with(&asleep, 60, 1, false);
    for workers in 2..=4 {
        let (other, _) = run_workers_with(&asleep, 60, workers, false);
        assert_same(&one, &other);
    }
}

#[test]
fn points_solved_together_are_bit_identical_on_1_to_4_real_workers() {
    // `solve_points_together` (issue 36) in the SIMD lanes and in the overflow's scalar
    // constraints alike: the pyramid with its plank's overflow and the pusher.
    let pyramid = pyramid_with_overflow_and_kinematic();
    let together = |s: &mut StepSettings| s.solve_points_together = true;
    let (one, overflow) = run_workers_tweaked(&pyramid, 60, 1, true, together);
    assert!(overflow >= 10, "overflow {overflow}");
    for workers in 2..=4 {
        let (other, _) = run_workers_tweaked(&pyramid, 60, workers, true, together);
        assert_same(&one, &other);
    }
    // And it changes the result: the setting really ran.
    let in_turn = |s: &mut StepSettings| s.solve_points_together = false;
    let (apart, _) = run_workers_tweaked(&pyramid, 60, 1, true, in_turn);
    assert_ne!(one.hash, apart.hash);
}

#[test]
fn impacts_that_bounce_are_bit_identical_on_1_to_4_real_workers() {
    // `impacts_bounce` (issue 36, the default): whether the passes go on is a count summed over every
    // constraint, so the pass count of every step, and with it the state, must not depend on
    // the workers. The elastic box (eight-lane constraints of restitution 1) with every stage
    // split, so that its 40 balls' passes really are shared; and spinner at the defaults
    // (restitution 0.1 everywhere, a dense pile the paddle stirs, whose passes run long).
    let elastic = tumble_scene::builtin::build("elastic_box").expect("elastic_box");
    let spinner = tumble_scene::builtin::build("spinner").expect("spinner");
    for (scene, steps, split) in [(&elastic, 300, true), (&spinner, 60, false)] {
        let run = |workers: usize| {
            let mut w = world(scene);
            w.settings_mut().impacts_bounce = true;
            if split {
                w.set_wide_thresholds(WideThresholds::ALWAYS);
            }
            w.set_workers_beyond_cores(true);
            w.set_thread_count(workers);
            let (mut passes, mut shared) = (Vec::new(), 0);
            for _ in 0..steps {
                w.step(scene.dt, scene.substeps);
                let p = w.profile();
                passes.push(p.restitution_passes);
                shared += usize::from(p.solver_workers == workers);
            }
            assert!(all_finite(&w), "{}: non-finite state", scene.name);
            let label = format!("{} on {workers} workers", scene.name);
            (Run::of(label, &w, 0, EventLog::default()), passes, shared)
        };
        let (one, passes, _) = run(1);
        // The setting really ran: steps of several passes.
        assert!(
            passes.iter().any(|&n| n > 1),
            "{}: passes {passes:?}",
            scene.name
        );
        for workers in 2..=4 {
            let (other, other_passes, shared) = run(workers);
            assert!(
                shared > 0,
                "{}: never solved on {workers} workers",
                scene.name
            );
            assert_eq!(passes, other_passes, "{} on {workers} workers", scene.name);
            assert_same(&one, &other);
        }
        // And it changes the result.
        let (box2d_rule, _) =
            run_workers_tweaked(scene, steps, 1, false, |s| s.impacts_bounce = false);
        assert_ne!(one.hash, box2d_rule.hash, "{}", scene.name);
    }
}

#[test]
fn the_new_shapes_are_bit_identical_on_1_to_4_real_workers() {
    // spinner: a loop chain, capsules, circles, squares and a rounded paddle, sleeping on; 90
    // steps (1.5 s), in which the bodies fall into the ring's bottom and the paddle, turning
    // from the start, sweeps through them. many_pyramids stands on 20 segments: 60 steps.
    let spinner = tumble_scene::builtin::build("spinner").expect("spinner");
    let pyramids = tumble_scene::builtin::build("many_pyramids").expect("many_pyramids");
    for (scene, steps) in [(&spinner, 90), (&pyramids, 60)] {
        let (one, _) = run_workers_with(scene, steps, 1, false);
        assert!(
            one.contacts > 1000,
            "{}: {} contacts",
            scene.name,
            one.contacts
        );
        for workers in 2..=4 {
            let (other, _) = run_workers_with(scene, steps, workers, false);
            assert_same(&one, &other);
        }
    }
}

/// Every joint type in one scene, sleeping on: a chain of 10 links on revolute joints (the
/// first with a limit, the second with a spring), a slider on a prismatic motor, a cart on two
/// wheel joints driven by a motor, a rope and a spring on distance joints, a soft weld, a
/// motor joint, a filter joint, and a hub tied by 30 distance joints to 30 balls around it:
/// more joints on one body than there are colours, so some go to the overflow.
fn every_joint() -> SceneDef {
    use tumble_physics::joint::{AngularMotor, LinearMotor, Spring};
    let mut scene = SceneDef::new("every_joint");
    let rect = |hx: f32, hy: f32| ShapeDef::Box {
        half_extents: [hx, hy],
        radius: 0.0,
    };
    let ball = |r: f32| ShapeDef::Circle { radius: r };
    let ground = scene.push(
        BodyDef::new(rect(50.0, 0.5))
            .kind(BodyKind::Static)
            .at(0.0, -0.5),
    );
    // The chain, hanging sideways from (−20, 12) so it swings.
    let mut prev = ground;
    for k in 0..10 {
        let x = -20.0 + 0.5 + k as f32;
        let link = scene.push(BodyDef::new(rect(0.5, 0.1)).at(x, 12.0));
        let mut joint = JointDef::hinge([prev, link].map(BodyId::scene), [x - 0.5, 12.0]);
        if let JointDef::Revolute { limit, spring, .. } = &mut joint {
            match k {
                1 => *limit = Some([-0.5, 0.5]),
                2 => {
                    *spring = Some(Spring {
                        hertz: 2.0,
                        damping_ratio: 0.3,
                    })
                }
                _ => {}
            }
        }
        scene.joints.push(joint);
        prev = link;
    }
    // A slider driven up a 30° rail.
    let slider = scene.push(BodyDef::new(rect(0.3, 0.3)).at(-5.0, 5.0));
    let (c, s) = (30f32.to_radians().cos(), 30f32.to_radians().sin());
    scene.joints.push(JointDef::Prismatic {
        force_threshold: f32::INFINITY,
        torque_threshold: f32::INFINITY,
        bodies: [ground, slider].map(BodyId::scene),
        anchor: [-5.0, 5.0],
        axis: [c, s],
        limit: Some([-2.0, 2.0]),
        motor: Some(LinearMotor {
            speed: 1.0,
            max_force: 50.0,
        }),
        spring: None,
        collide_connected: false,
    });
    // A cart on two wheels, driven.
    let chassis = scene.push(BodyDef::new(rect(1.0, 0.25)).at(0.0, 1.2));
    for x in [-0.7f32, 0.7] {
        let wheel = scene.push(BodyDef::new(ball(0.4)).at(x, 0.6).friction(0.9));
        scene.joints.push(JointDef::Wheel {
            force_threshold: f32::INFINITY,
            torque_threshold: f32::INFINITY,
            bodies: [chassis, wheel].map(BodyId::scene),
            anchor: [x, 0.6],
            axis: [0.0, 1.0],
            limit: Some([-0.2, 0.2]),
            motor: Some(AngularMotor {
                speed: -4.0,
                max_torque: 20.0,
            }),
            spring: Some(Spring {
                hertz: 4.0,
                damping_ratio: 0.7,
            }),
            collide_connected: false,
        });
    }
    // A rope and a spring from the ground, a soft weld, a motor joint and a filter joint.
    let on_rope = scene.push(BodyDef::new(ball(0.3)).at(8.0, 6.0));
    scene.joints.push(JointDef::Distance {
        force_threshold: f32::INFINITY,
        torque_threshold: f32::INFINITY,
        bodies: [ground, on_rope].map(BodyId::scene),
        anchors: [[6.0, 8.0], [8.0, 6.0]],
        length: Some(3.0),
        limit: Some([0.0, 3.0]),
        spring: Some(Spring {
            hertz: 0.0,
            damping_ratio: 0.0,
        }),
        collide_connected: false,
    });
    let on_spring = scene.push(BodyDef::new(ball(0.3)).at(10.0, 6.0));
    scene.joints.push(JointDef::Distance {
        force_threshold: f32::INFINITY,
        torque_threshold: f32::INFINITY,
        bodies: [ground, on_spring].map(BodyId::scene),
        anchors: [[10.0, 8.0], [10.0, 6.0]],
        length: None,
        limit: None,
        spring: Some(Spring {
            hertz: 3.0,
            damping_ratio: 0.2,
        }),
        collide_connected: false,
    });
    let welded = scene.push(BodyDef::new(rect(0.5, 0.5)).at(12.5, 4.0));
    scene.joints.push(JointDef::Weld {
        force_threshold: f32::INFINITY,
        torque_threshold: f32::INFINITY,
        bodies: [on_spring, welded].map(BodyId::scene),
        anchor: [11.0, 5.0],
        linear_hertz: 5.0,
        angular_hertz: 3.0,
        linear_damping_ratio: 0.7,
        angular_damping_ratio: 0.7,
        collide_connected: false,
    });
    let driven = scene.push(BodyDef::new(rect(0.4, 0.4)).at(15.0, 3.0));
    scene.joints.push(JointDef::Motor {
        force_threshold: f32::INFINITY,
        torque_threshold: f32::INFINITY,
        bodies: [ground, driven].map(BodyId::scene),
        linear_offset: Some([16.0, 4.5]),
        angular_offset: Some(1.0),
        max_force: 200.0,
        max_torque: 50.0,
        correction_factor: 0.3,
        collide_connected: false,
    });
    let apart = scene.push(BodyDef::new(rect(0.4, 0.4)).at(15.0, 0.4));
    scene.joints.push(JointDef::Filter {
        bodies: [driven, apart].map(BodyId::scene),
    });
    // The hub and its 30 balls.
    let hub = scene.push(BodyDef::new(ball(1.0)).at(25.0, 8.0));
    for k in 0..30 {
        let a = k as f32 * std::f32::consts::TAU / 30.0;
        let p = [25.0 + 2.5 * a.cos(), 8.0 + 2.5 * a.sin()];
        let b = scene.push(BodyDef::new(ball(0.2)).at(p[0], p[1]));
        scene.joints.push(JointDef::Distance {
            force_threshold: f32::INFINITY,
            torque_threshold: f32::INFINITY,
            bodies: [hub, b].map(BodyId::scene),
            anchors: [[25.0, 8.0], p],
            length: None,
            limit: None,
            spring: None,
            collide_connected: false,
        });
    }
    scene
}

#[test]
fn joints_are_bit_identical_on_1_to_4_real_workers() {
    // joint_grid: 19794 joints, solved on every worker (strict); 12 steps (the debug build
    // CI runs takes seconds a step for it on 4 workers). tumbler: the motor-driven drum
    // churning 2025 boxes, 30 steps. every_joint: each joint type, an overflow of joints, a
    // chain solved as one, sleeping on, 240 steps (4 s: the chain and the springs settle).
    let grid = tumble_scene::builtin::build("joint_grid").expect("joint_grid");
    let (one, _) = run_workers_with(&grid, 12, 1, true);
    for workers in 2..=4 {
        let (other, _) = run_workers_with(&grid, 12, workers, true);
        assert_same(&one, &other);
    }
    let tumbler = tumble_scene::builtin::build("tumbler").expect("tumbler");
    let every = every_joint();
    for (scene, steps) in [(&tumbler, 30), (&every, 240)] {
        let (one, overflow) = run_workers_with(scene, steps, 1, false);
        if scene.name == "every_joint" {
            assert!(overflow > 0, "the hub's joints reach the overflow");
        }
        for workers in 2..=4 {
            let (other, _) = run_workers_with(scene, steps, workers, false);
            assert_same(&one, &other);
        }
    }
}

#[test]
fn the_thread_count_changes_mid_run_on_a_parallel_scene() {
    // large_pyramid solves on several workers every step (its 14,950 touching contacts are
    // far above the 256 below which one worker solves alone); the worker count changes every
    // 5 steps and the result is the same as on one.
    let scene = tumble_scene::builtin::build("large_pyramid").expect("large_pyramid");
    let (one, _) = run_workers(&scene, 40, 1);
    let mut w = world(&scene);
    w.set_workers_beyond_cores(true);
    let mut log = EventLog::default();
    for step in 0..40 {
        let workers = (step / 5 % 4) as usize + 1;
        w.set_thread_count(workers);
        w.step(scene.dt, scene.substeps);
        log.read(&w, true);
        assert_eq!(w.profile().solver_workers, workers, "step {step}");
    }
    let switching = Run::of(
        "large_pyramid, 1-4 workers changing every 5 steps".into(),
        &w,
        0,
        log,
    );
    assert_same(&one, &switching);
}

#[test]
fn rain_making_and_destroying_ragdolls_is_bit_identical_on_1_to_4_real_workers() {
    // Box2D's rain on a shorter schedule, through its own script (stateless: a step number
    // names its wave): columns 0, 1 and 2 made at steps 0, 8 and 16 (825 bodies, 750 sprung,
    // limited, motor-braked hinges), the ragdolls landing from 40 m from step 200 on (column
    // 0's touch the ground from about step 205); at step 215, the wave that replaces column
    // 0 (rain's step 320) destroys its five groups, lying on the ground, and makes them again
    // at the top; 230 steps, sleeping on. The events (contacts beginning and ending, hits,
    // the destroyed groups' contacts ended between steps) are the same on every count.
    use tumble_scene::builtin::rain;
    let scene = tumble_scene::builtin::build("rain").expect("rain");
    let runs: Vec<Run> = (1..=4)
        .map(|workers| {
            let mut w = world(&scene);
            w.set_workers_beyond_cores(true);
            w.set_thread_count(workers);
            let mut log = EventLog::default();
            let (mut touching_destroyed, mut ended_by_destroy) = (0, 0);
            for step in 0..230u64 {
                let wave = match step {
                    0 | 8 | 16 => Some(step),
                    215 => Some(rain::DELAY * rain::COLUMNS as u64),
                    _ => None,
                };
                if let Some(wave) = wave {
                    let before = log.events.len();
                    if step == 215 {
                        touching_destroyed = touching_of_column_0(&w);
                    }
                    rain::step(wave, &mut w);
                    log.read(&w, false);
                    if step == 215 {
                        ended_by_destroy = log.events[before..]
                            .iter()
                            .filter(|(_, e)| matches!(e, Event::ContactEnd { .. }))
                            .count();
                    }
                }
                w.step(scene.dt, scene.substeps);
                log.read(&w, true);
            }
            assert!(
                all_finite(&w),
                "rain on {workers} workers: non-finite state"
            );
            assert_eq!(w.body_count(), 1 + 3 * 5 * 55);
            assert!(w.contact_count() > 100, "the ragdolls have landed");
            // Destroying column 0's landed groups ended their touching contacts at once, as
            // many as touched just before.
            assert_eq!(ended_by_destroy, touching_destroyed);
            assert!(ended_by_destroy > 0, "column 0 had not landed");
            Run::of(format!("rain on {workers} workers"), &w, 0, log)
        })
        .collect();
    for other in &runs[1..] {
        assert_same(&runs[0], other);
    }
}

/// Touching contacts of rain's column 0 (its bodies' user data names the column).
fn touching_of_column_0(w: &World) -> usize {
    use tumble_scene::builtin::rain;
    let column_0: std::collections::HashSet<BodyId> = w
        .body_ids()
        .filter(|&id| (0..rain::ROWS).any(|row| w.user_data(id) == Ok(rain::tag(row, 0))))
        .collect();
    w.contacts()
        .filter(|c| {
            c.manifold.count > 0 && (column_0.contains(&c.body_a) || column_0.contains(&c.body_b))
        })
        .count()
}

#[test]
fn spinners_bounces_agree_packed_eight_to_a_constraint_or_not() {
    // Impacts that bounce (the default) in `spinner`, whose bounce passes stop at their visit
    // budget in most steps: the budget and each pass's visits are counted in contacts, so the
    // eight-lane constraints (a lane per contact) and the scalar ones (a constraint per
    // contact) take the same passes and end in the same bits. (Counted in listed
    // constraints, as first written, eight lanes weighed as one contact, and the scalar run
    // took more passes.)
    let scene = tumble_scene::builtin::build("spinner").expect("spinner");
    let run = |simd: bool| {
        let mut w = world(&scene);
        w.settings_mut().simd = simd;
        w.set_thread_count(1);
        let passes: Vec<u32> = (0..60)
            .map(|_| {
                w.step(scene.dt, scene.substeps);
                w.profile().restitution_passes
            })
            .collect();
        (w.state_hash(), passes)
    };
    let (packed, packed_passes) = run(true);
    let (scalar, scalar_passes) = run(false);
    assert!(packed_passes.iter().any(|&n| n > 2), "{packed_passes:?}");
    assert_eq!(packed_passes, scalar_passes);
    assert_eq!(packed, scalar);
}
