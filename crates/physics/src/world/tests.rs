use super::*;
use crate::def::{BodyDef, ShapeDef};
use crate::joint::{AngularMotor, JointDef, JointKind, Spring};

fn ball_on_ground() -> World {
    let mut w = World::new(StepSettings::default());
    w.create_body(
        &BodyDef::new(ShapeDef::Box {
            half_extents: [5.0, 0.5],
            radius: 0.0,
        })
        .kind(BodyKind::Static),
    )
    .unwrap();
    w.create_body(&BodyDef::new(ShapeDef::Circle { radius: 0.5 }).at(0.0, 1.0))
        .unwrap();
    w
}

#[test]
fn kinetic_energy_is_half_m_v_squared_plus_half_i_w_squared_of_dynamic_bodies() {
    let mut w = ball_on_ground();
    w.set_velocity(BodyId::scene(1), Vec2::new(3.0, 4.0), 2.0)
        .unwrap();
    // Disc of radius 0.5, density 1: m = π/4, I = m r²/2 = π/32; the static ground counts
    // nothing. 1e-6 relative: f32 mass and inertia summed in f64.
    let m = std::f64::consts::PI / 4.0;
    let expected = 0.5 * m * 25.0 + 0.5 * (m * 0.125) * 4.0;
    let e = w.kinetic_energy();
    assert!((e / expected - 1.0).abs() < 1e-6, "{e} vs {expected}");
}

#[test]
fn is_finite_sees_one_non_finite_velocity() {
    // set_velocity refuses non-finite input, so the state is written directly.
    let mut w = ball_on_ground();
    assert!(w.is_finite());
    w.bodies.states[1].v.x = f32::NAN;
    assert!(!w.is_finite());
    w.bodies.states[1].v.x = 0.0;
    w.bodies.states[1].w = f32::INFINITY;
    assert!(!w.is_finite());
    w.bodies.states[1].w = 0.0;
    w.bodies.sims[1].xf.p.y = f32::NEG_INFINITY;
    assert!(!w.is_finite());
}

/// One ball in the air, alone: nothing it touches can carry a bad number back to it.
fn lone_ball() -> World {
    let mut w = World::new(StepSettings::default());
    w.create_body(&BodyDef::new(ShapeDef::Circle { radius: 0.5 }).at(0.0, 10.0))
        .unwrap();
    w
}

#[test]
fn the_guard_counts_every_body_it_stops_and_snapshots_keep_the_count() {
    let mut w = lone_ball();
    for _ in 0..3 {
        w.step(1.0 / 60.0, 4);
    }
    assert_eq!(w.non_finite_bodies(), 0);
    // set_velocity refuses non-finite input, so the state is written directly: what a
    // broken upstream (a bad solve, a bad mass) would leave.
    w.bodies.states[0].v = Vec2::new(f32::NAN, 1.0);
    let before = w.body_view(0).position;
    w.step(1.0 / 60.0, 4);
    // The guard hid it: the state is finite again, the body kept its last finite pose.
    assert!(w.is_finite());
    assert_eq!(w.body_view(0).position, before);
    assert_eq!(w.profile().non_finite, 1);
    assert_eq!(w.non_finite_bodies(), 1);
    // Later healthy steps forget it in the profile but not in the total.
    for _ in 0..10 {
        w.step(1.0 / 60.0, 4);
    }
    assert_eq!(w.profile().non_finite, 0);
    assert_eq!(w.non_finite_bodies(), 1);
    // Through JSON and back, the count survives, and keeps counting from there.
    let text = serde_json::to_string(&w.snapshot()).unwrap();
    let mut restored = World::from_snapshot(serde_json::from_str(&text).unwrap()).unwrap();
    assert_eq!(restored.non_finite_bodies(), 1);
    restored.bodies.states[0].w = f32::NAN;
    restored.step(1.0 / 60.0, 4);
    assert!(restored.is_finite());
    assert_eq!(restored.non_finite_bodies(), 2);
}

#[test]
fn a_snapshot_without_the_count_loads_as_zero() {
    let mut value = serde_json::to_value(lone_ball().snapshot()).unwrap();
    let fields = value.as_object_mut().unwrap();
    assert!(fields.remove("non_finite_bodies").is_some());
    let snap: WorldSnapshot = serde_json::from_value(value).unwrap();
    assert_eq!(World::from_snapshot(snap).unwrap().non_finite_bodies(), 0);
}

#[test]
fn step_refuses_a_subnormal_or_non_positive_dt() {
    let mut w = lone_ball();
    let hash = w.state_hash();
    let tiny = f32::MIN_POSITIVE / 4.0;
    assert!(tiny > 0.0 && !tiny.is_normal());
    // A subnormal dt, a normal dt whose substep is subnormal, zero, negative, NaN,
    // infinity, and no substeps: none steps.
    for (dt, substeps) in [
        (tiny, 1),
        (f32::MIN_POSITIVE, 4),
        (0.0, 4),
        (-1.0 / 60.0, 4),
        (f32::NAN, 4),
        (f32::INFINITY, 4),
        (1.0 / 60.0, 0),
    ] {
        assert!(!World::steppable(dt, substeps), "{dt} {substeps}");
        w.step(dt, substeps);
        assert_eq!(w.step_count(), 0, "{dt} {substeps}");
        assert_eq!(w.state_hash(), hash, "{dt} {substeps}");
    }
    // The smallest dt it takes runs and stays finite.
    assert!(World::steppable(f32::MIN_POSITIVE, 1));
    w.step(f32::MIN_POSITIVE, 1);
    assert_eq!(w.step_count(), 1);
    assert!(w.is_finite());
    assert_eq!(w.non_finite_bodies(), 0);
}

#[test]
fn step_settings_validate_refuses_each_bad_knob() {
    assert_eq!(StepSettings::default().validate(), Ok(()));
    let refused = |change: fn(&mut StepSettings), field: &str, words: &[&str]| {
        let mut s = StepSettings::default();
        change(&mut s);
        let e = s.validate().expect_err(field);
        assert_eq!(e.field, field);
        let text = e.to_string();
        assert!(text.contains(&format!("`{field}`")), "{text}");
        for w in words {
            assert!(text.contains(w), "{text} lacks {w}");
        }
    };
    refused(
        |s| s.relax_iterations = 0,
        "relax_iterations",
        &["friction"],
    );
    refused(
        |s| s.restitution_iterations = 0,
        "restitution_iterations",
        &["1 or more"],
    );
    refused(|s| s.contact_hertz = -1.0, "contact_hertz", &["-1", ">= 0"]);
    refused(|s| s.contact_hertz = f32::NAN, "contact_hertz", &["NaN"]);
    refused(
        |s| s.contact_damping_ratio = -0.5,
        "contact_damping_ratio",
        &["-0.5"],
    );
    refused(
        |s| s.contact_damping_ratio = f32::INFINITY,
        "contact_damping_ratio",
        &["inf"],
    );
    refused(|s| s.max_push_speed = -3.0, "max_push_speed", &["-3"]);
    refused(|s| s.max_push_speed = f32::NAN, "max_push_speed", &["NaN"]);
    refused(
        |s| s.restitution_threshold = -1.0,
        "restitution_threshold",
        &["-1"],
    );
    refused(
        |s| s.restitution_threshold = f32::INFINITY,
        "restitution_threshold",
        &["inf"],
    );
    refused(|s| s.max_linear_speed = -1.0, "max_linear_speed", &["> 0"]);
    refused(|s| s.max_linear_speed = 0.0, "max_linear_speed", &["> 0"]);
    refused(
        |s| s.max_linear_speed = f32::INFINITY,
        "max_linear_speed",
        &["inf"],
    );
    refused(|s| s.gravity.y = f32::NAN, "gravity", &["finite"]);
    // Zero is a usable value where it means "off": rigid contacts, no damping, no push-out,
    // every approach bounces.
    let zeros = StepSettings {
        contact_hertz: 0.0,
        contact_damping_ratio: 0.0,
        max_push_speed: 0.0,
        restitution_threshold: 0.0,
        ..StepSettings::default()
    };
    assert_eq!(zeros.validate(), Ok(()));
}

#[test]
fn a_snapshot_with_bad_settings_is_refused() {
    let mut snap = ball_on_ground().snapshot();
    snap.settings.relax_iterations = 0;
    let e = World::from_snapshot(snap).err().expect("refused");
    assert!(e.to_string().contains("relax_iterations"), "{e}");
}

#[test]
fn a_body_whose_mass_or_inertia_f32_cannot_invert_is_refused() {
    let mut w = ball_on_ground();
    let circle = |r: f32| BodyDef::new(ShapeDef::Circle { radius: r });
    // Radius 1e-20 m: mass π·1e-40 kg is subnormal, its inverse infinite.
    let e = w.create_body(&circle(1e-20)).unwrap_err().to_string();
    for word in [
        "body 2",
        "`density`",
        "mass",
        "raise the density",
        "enlarge",
    ] {
        assert!(e.contains(word), "{e} lacks {word}");
    }
    // A subnormal density: the same.
    let e = w
        .create_body(&circle(1.0).density(1e-40))
        .unwrap_err()
        .to_string();
    assert!(e.contains("`density`") && e.contains("mass"), "{e}");
    // A mass too large for f32.
    let e = w
        .create_body(&circle(1000.0).density(1e35))
        .unwrap_err()
        .to_string();
    assert!(e.contains("lower the density"), "{e}");
    // Radius 1e-10 m: the mass (3e-20 kg) is fine, the inertia (1.6e-40) underflows.
    let e = w.create_body(&circle(1e-10)).unwrap_err().to_string();
    for word in ["body 2", "`shape`", "rotational inertia", "fixed_rotation"] {
        assert!(e.contains(word), "{e} lacks {word}");
    }
    // A body that cannot rotate needs no inverse inertia, and one refused body leaves no
    // trace: ids continue from 2.
    assert_eq!(
        w.create_body(&circle(1e-10).fixed_rotation(true)),
        Ok(BodyId::scene(2))
    );
    // Static bodies have no mass to invert.
    assert!(w.create_body(&circle(1e-20).kind(BodyKind::Static)).is_ok());
    // From a scene, the index is the body's place in it.
    let mut scene = SceneDef::new("tiny");
    scene.push(circle(1.0));
    scene.push(circle(1e-20));
    let e = World::from_scene(&scene, &Limits::default())
        .err()
        .expect("refused")
        .to_string();
    assert!(e.starts_with("body 1: field `density`"), "{e}");
}

#[test]
fn impulse_changes_velocity_by_inverse_mass() {
    let mut w = ball_on_ground();
    let m = w.mass(BodyId::scene(1)).unwrap();
    // Disc of radius 0.5 at density 1: m = π/4.
    assert!((m - std::f32::consts::FRAC_PI_4).abs() < 1e-6);
    w.apply_linear_impulse(
        BodyId::scene(1),
        Vec2::new(2.0, 0.0),
        Vec2::new(0.0, 1.5),
        true,
    )
    .unwrap();
    let b = w.body_view(1);
    assert!((b.linear_velocity.x - 2.0 / m).abs() < 1e-5);
    // Off-centre by +0.5 in y: torque r × J = 0.5·0 − 0.5·2 = −1; w = −1 / (m r²/2).
    assert!((b.angular_velocity + 1.0 / (0.5 * m * 0.25)).abs() < 1e-4);
    // Static bodies ignore it.
    w.apply_linear_impulse(BodyId::scene(0), Vec2::new(5.0, 0.0), Vec2::ZERO, true)
        .unwrap();
    assert_eq!(w.body_view(0).linear_velocity, Vec2::ZERO);
}

#[test]
fn body_at_picks_the_shape_under_the_point() {
    let w = ball_on_ground();
    assert_eq!(w.body_at(Vec2::new(0.1, 1.2)), Some(BodyId::scene(1)));
    assert_eq!(w.body_at(Vec2::new(4.0, 0.0)), Some(BodyId::scene(0)));
    assert_eq!(w.body_at(Vec2::new(0.0, 3.0)), None);
}

#[test]
fn thread_count_changes_between_steps_keep_the_result() {
    // A 30-row pyramid: 465 boxes, about 1,400 touching contacts, well above the 256 below
    // which one worker solves alone, so every step here really is solved by the workers
    // asked for (1 to 3, beyond the cores where there are fewer; checked each step).
    let pyramid = || {
        let mut w = World::new(StepSettings::default());
        w.set_workers_beyond_cores(true);
        // A 465-body pyramid is inline by default: split it anyway.
        w.set_wide_thresholds(WideThresholds::ALWAYS);
        box_pyramid(&mut w, 30, 40.0);
        w
    };
    let run = |switch: bool| {
        let mut w = pyramid();
        w.set_thread_count(1);
        for i in 0..30 {
            let workers = if switch { 1 + i % 3 } else { 1 };
            w.set_thread_count(workers);
            w.step(1.0 / 60.0, 4);
            assert!(w.profile().touching > 256);
            assert_eq!(w.profile().solver_workers, workers, "step {i}");
        }
        w.state_hash()
    };
    assert_eq!(run(false), run(true));
}

#[test]
fn a_solve_split_only_where_it_pays_times_both_ways_and_keeps_the_bits() {
    // A 45-row pyramid: 1,035 boxes, about 3,000 touching contacts, above the default
    // thresholds' split of the substeps at 2 threads, where `solve_by_payoff` times them
    // on one worker now and then: within 40 steps (a probe after the first 8) the solver
    // runs both split and on one worker, whichever the clock prefers, and the state is the
    // one thread's bit for bit.
    let run = |threads: usize| {
        let mut w = World::new(StepSettings::default());
        assert!(w.wide_thresholds().solve_by_payoff);
        box_pyramid(&mut w, 45, 60.0);
        w.set_thread_count(threads);
        let mut workers = std::collections::BTreeSet::new();
        let mut probes = 0;
        for _ in 0..40 {
            w.step(1.0 / 60.0, 4);
            assert!(w.profile().touching > 2 * w.wide_thresholds().solve);
            workers.insert(w.profile().solver_workers);
            probes += usize::from(w.profile().solver_probe);
        }
        // Probes of two steps: the first after 8 steps, the next 8 steps after one that
        // switched and 16 or 32 after one that did not, so at most four in 40 steps (each
        // switching) and at least one; none at 1 thread.
        assert!(probes <= 8, "{probes} probe steps");
        if threads > 1 && crate::default_thread_count() > 1 {
            assert!(probes >= 2, "{probes} probe steps");
        } else {
            assert_eq!(probes, 0);
        }
        (w.state_hash(), workers)
    };
    let (one, alone) = run(1);
    assert_eq!(alone, [1].into());
    let (two, workers) = run(2);
    if crate::default_thread_count() > 1 {
        assert_eq!(workers, [1, 2].into(), "both ways timed");
    }
    assert_eq!(one, two);
}

/// A static ground `ground_half_width` each side of the origin (0.5 thick, top at y = 0)
/// and a pyramid of `rows` rows of unit boxes standing on it, centred on x = 0.
fn box_pyramid(w: &mut World, rows: usize, ground_half_width: f32) {
    let ground = BodyDef::new(ShapeDef::Box {
        half_extents: [ground_half_width, 0.5],
        radius: 0.0,
    });
    w.create_body(&ground.kind(BodyKind::Static)).unwrap();
    for row in 0..rows {
        for col in 0..(rows - row) {
            let x = col as f32 + row as f32 * 0.5 - rows as f32 * 0.5;
            let unit = ShapeDef::Box {
                half_extents: [0.5, 0.5],
                radius: 0.0,
            };
            w.create_body(&BodyDef::new(unit).at(x, 1.0 + row as f32))
                .unwrap();
        }
    }
}

/// An 8-row pyramid of boxes with 20 bouncy circles falling on it.
fn pyramid_in_rain(settings: StepSettings) -> World {
    let mut w = World::new(settings);
    box_pyramid(&mut w, 8, 20.0);
    for i in 0..20 {
        let shape = ShapeDef::Circle { radius: 0.25 };
        let body = BodyDef::new(shape)
            .at(i as f32 * 0.4 - 4.0, 12.0)
            .restitution(0.3);
        w.create_body(&body).unwrap();
    }
    w
}

#[test]
fn a_kept_colouring_is_the_one_a_fresh_colouring_gives() {
    // One world keeps last step's colouring whenever the touching pairs repeat; the other
    // colours from scratch every step. The colouring is a function of those pairs, so
    // both must agree exactly, colour for colour and bit for bit.
    let mut kept = pyramid_in_rain(StepSettings::default());
    let mut fresh = pyramid_in_rain(StepSettings::default());
    let mut reused = 0;
    for _ in 0..240 {
        fresh.solver.forget_coloring();
        kept.step(1.0 / 60.0, 4);
        fresh.step(1.0 / 60.0, 4);
        assert!(fresh.solver.recolored);
        reused += usize::from(!kept.solver.recolored);
        assert_eq!(kept.contact_colors(), fresh.contact_colors());
        assert_eq!(kept.state_hash(), fresh.state_hash());
    }
    // The rain bounces, rolls off and settles: most of the run has touching pairs that
    // repeat, so the kept path was taken (its count is the test's reason to exist).
    assert!(reused > 60, "colouring kept on {reused} of 240 steps");
}

#[test]
fn simd_and_scalar_solvers_agree_bit_for_bit() {
    // Both paths do the same per-lane operations in the same order, with no fused
    // multiply-add, so the whole state must match exactly, not within a tolerance.
    // With `impacts_bounce` too: the lanes' threshold mask and the moved count that decides
    // whether another restitution pass runs (each pass count is compared, step by step).
    // And with a manifold's points solved in turn (Box2D's rule) as well as together (the
    // default): the lanes' `together` mask is decided by the eight-lane build, the scalar
    // constraints' flag by `contact_solver::points_together`.
    let run = |simd: bool, avx: bool, impacts: bool, together: bool| {
        let mut w = pyramid_in_rain(StepSettings {
            impacts_bounce: impacts,
            solve_points_together: together,
            ..StepSettings::default()
        });
        w.settings_mut().simd = simd;
        w.solver.use_avx = avx;
        let mut passes = Vec::new();
        for _ in 0..120 {
            w.step(1.0 / 60.0, 4);
            passes.push(w.profile().restitution_passes);
        }
        assert!(w.profile().touching > 50);
        (w.state_hash(), passes)
    };
    let mut hashes = Vec::new();
    for (impacts, together) in [(false, true), (true, true), (false, false), (true, false)] {
        // The 8-lane kernels in AVX2 registers (where the CPU has AVX2; elsewhere both runs
        // take the portable path) against the portable f32x8 kernels, and against scalar.
        let portable = run(true, false, impacts, together);
        assert_eq!(run(true, true, impacts, together), portable);
        assert_eq!(run(false, false, impacts, together), portable);
        // With the setting, the rain's bounces took more than one pass in some step.
        assert_eq!(
            portable.1.iter().any(|&n| n > 1),
            impacts,
            "{:?}",
            portable.1
        );
        hashes.push(portable.0);
    }
    // Each setting changed the result: every run really took its path.
    hashes.sort_unstable();
    hashes.dedup();
    assert_eq!(hashes.len(), 4);
}

/// A 16 × 16 net of discs hung from a static bar by hinges (each disc joined to the one above
/// and the one to its left, as in `joint_grid`), every seventh hinge limited to ±0.3 rad,
/// swinging under gravity. With `rows`, the limits leave out the start, every third hinge has a
/// spring (its rest angle within 0.012 rad of ±π for some, so the angle wraps), every fifth a
/// motor (friction for some, a drive for others), and one disc in eleven cannot turn (its
/// hinges turn its neighbour alone): every mix of rows in a group of eight.
fn hinge_net(rows: bool) -> World {
    let mut w = World::new(StepSettings::default());
    let bar = w
        .create_body(
            &BodyDef::new(ShapeDef::Box {
                half_extents: [10.0, 0.1],
                radius: 0.0,
            })
            .kind(BodyKind::Static)
            .at(7.5, 0.5),
        )
        .unwrap();
    let filter = crate::def::Filter {
        category: 2,
        mask: !2,
        group: 0,
    };
    let n = 16;
    let mut made = 0;
    for k in 0..n {
        for i in 0..n {
            let (x, y) = (k as f32, -(i as f32));
            let disc = w
                .create_body(
                    &BodyDef::new(ShapeDef::Circle { radius: 0.4 })
                        .at(x, y)
                        .filter(filter)
                        .fixed_rotation(rows && (k * n + i) % 11 == 0),
                )
                .unwrap();
            // Bodies made in order take slots in order: the disc above is one slot back,
            // the one to the left a column (n slots) back.
            let back = |by: u32| BodyId::scene((disc.index - by) as usize);
            let above = if i == 0 { bar } else { back(1) };
            let mut joints = vec![JointDef::hinge([above, disc], [x, y + 0.5])];
            if k > 0 {
                joints.push(JointDef::hinge([back(n), disc], [x - 0.5, y]));
            }
            for mut def in joints {
                made += 1;
                if let JointDef::Revolute {
                    limit,
                    spring,
                    motor,
                    ..
                } = &mut def
                {
                    if made % 7 == 0 {
                        // The net bends its hinges by hundredths of a radian: with rows,
                        // limits that leave out the start, one side each, so that both bite.
                        *limit = Some(match (rows, made % 2) {
                            (false, _) => [-0.3, 0.3],
                            (true, 0) => [0.005, 0.3],
                            (true, _) => [-0.3, -0.005],
                        });
                    }
                    if rows && made % 3 == 0 {
                        *spring = Some(Spring {
                            hertz: 2.0,
                            damping_ratio: 0.5,
                        });
                    }
                    if rows && made % 5 == 0 {
                        *motor = Some(AngularMotor {
                            speed: if made % 2 == 0 { 0.0 } else { 1.5 },
                            max_torque: 0.2,
                        });
                    }
                }
                let id = w.create_joint(&def).unwrap();
                if rows && made % 6 == 0 {
                    let JointKind::Revolute(r) = &mut w.joints.list[id.index as usize].kind else {
                        unreachable!()
                    };
                    r.target_angle = if made % 12 == 0 { 3.13 } else { -3.13 };
                }
            }
        }
    }
    // A push sideways, so that the net swings, and a spin each way, so that the limits are
    // reached and the springs' angles wrap.
    for b in 1..w.body_count() {
        let spin = if b % 2 == 0 { 6.0 } else { -6.0 };
        w.set_velocity(BodyId::scene(b), Vec2::new(2.0, 0.0), spin)
            .unwrap();
    }
    w
}

#[test]
fn hinges_eight_at_a_time_agree_with_one_at_a_time_bit_for_bit() {
    // The hinge kernel does each lane's operations in the order `Revolute::solve` does, so
    // the state and every joint's impulses must match exactly.
    let run = |rows: bool, simd: bool, avx: bool| {
        let mut w = hinge_net(rows);
        w.settings_mut().simd = simd;
        w.solver.use_avx = avx;
        let mut hashes = Vec::new();
        for _ in 0..90 {
            w.step(1.0 / 60.0, 4);
            hashes.push(w.state_hash());
        }
        let reactions: Vec<[u32; 3]> = w
            .joint_ids()
            .map(|id| {
                let (f, t) = w.joint_reaction(id).unwrap();
                [f.x.to_bits(), f.y.to_bits(), t.to_bits()]
            })
            .collect();
        assert_eq!(reactions.len(), 16 * 16 + 15 * 16);
        (hashes, reactions)
    };
    for rows in [false, true] {
        let portable = run(rows, true, false);
        assert_eq!(run(rows, true, true), portable);
        assert_eq!(run(rows, false, false), portable);
    }
}

#[test]
fn a_restored_snapshot_continues_bit_for_bit() {
    let mut w = ball_on_ground();
    for i in 0..12 {
        let body = BodyDef::new(ShapeDef::Box {
            half_extents: [0.3, 0.2],
            radius: 0.0,
        })
        .at(i as f32 * 0.5 - 3.0, 2.0 + i as f32 * 0.3)
        .angle(0.1 * i as f32);
        w.create_body(&body).unwrap();
    }
    for _ in 0..45 {
        w.step(1.0 / 60.0, 4);
    }
    // Through JSON: f32 values are written shortest-round-trip, so they read back exactly.
    let text = serde_json::to_string(&w.snapshot()).unwrap();
    let mut restored = World::from_snapshot(serde_json::from_str(&text).unwrap()).unwrap();
    restored.set_thread_count(1);
    // The pile settles and falls asleep within these steps: the most touching pairs seen
    // shows the snapshot carried a pile in contact, not bodies in flight.
    let mut touching = 0;
    for _ in 0..90 {
        w.step(1.0 / 60.0, 4);
        restored.step(1.0 / 60.0, 4);
        touching = touching.max(w.profile().touching);
        assert_eq!(w.state_hash(), restored.state_hash());
    }
    assert!(touching > 5);
    assert_eq!(w.step_count(), restored.step_count());
}

#[test]
fn a_corrupt_snapshot_is_refused() {
    let mut snap = ball_on_ground().snapshot();
    snap.states.pop();
    assert!(World::from_snapshot(snap).is_err());
}

#[test]
fn contact_colors_cover_the_touching_contacts() {
    let mut w = ball_on_ground();
    for _ in 0..30 {
        w.step(1.0 / 60.0, 4);
    }
    let colors = w.contact_colors();
    assert_eq!(colors.len(), w.profile().touching);
    // A dynamic body against a static one goes to the top colours (Box2D's rule).
    assert!(
        colors.iter().all(|&(_, c)| (1..23).contains(&c)),
        "{colors:?}"
    );
}

#[test]
fn user_data_tags_a_body_until_it_is_destroyed_and_survives_a_snapshot() {
    let mut w = ball_on_ground();
    let ball = w.body_id(1).unwrap();
    assert_eq!(w.user_data(ball).unwrap(), 0);
    w.set_user_data(ball, 0xfeed_beef_0000_0042).unwrap();
    let text = serde_json::to_string(&w.snapshot()).unwrap();
    let restored = World::from_snapshot(serde_json::from_str(&text).unwrap()).unwrap();
    assert_eq!(restored.user_data(ball).unwrap(), 0xfeed_beef_0000_0042);
    // A destroyed body's id is refused, and the next body in its slot starts untagged.
    w.destroy_body(ball).unwrap();
    assert!(w.user_data(ball).is_err());
    assert!(w.set_user_data(ball, 7).is_err());
    let again = w
        .create_body(&BodyDef::new(ShapeDef::Circle { radius: 0.5 }))
        .unwrap();
    assert_eq!(again.index, ball.index);
    assert_eq!(w.user_data(again).unwrap(), 0);
}

/// Two 1 m boxes flying at 30 m/s along x without gravity, A at the origin and B at `b`.
fn flying_pair(b: [f32; 2]) -> World {
    let unit = ShapeDef::Box {
        half_extents: [0.5, 0.5],
        radius: 0.0,
    };
    let mut w = World::new(StepSettings {
        gravity: Vec2::ZERO,
        ..StepSettings::default()
    });
    w.create_body(&BodyDef::new(unit.clone()).velocity(30.0, 0.0))
        .unwrap();
    w.create_body(&BodyDef::new(unit).at(b[0], b[1]).velocity(30.0, 0.0))
        .unwrap();
    w
}

/// Contact recycling and fast bodies (`step::recycle`). Two 1 m boxes, one on the other,
/// flying together at 30 m/s without gravity: each moves 0.5 m a step, twice its half
/// thickness, so both are fast, yet they barely move relative to each other and their
/// contact keeps its manifold (each step after the first is recycled). A 4 cm box sliding
/// at 1.2 m/s on a static floor without friction moves 2 cm a step: fast against its 2 cm
/// half thickness, and within the 5 cm recycling distance of where its manifold was made, so
/// only the rule for fast bodies recomputes it (every step).
#[test]
fn fast_bodies_recycle_contacts_with_each_other_but_not_with_static_ground() {
    let mut w = flying_pair([0.0, 1.0]);
    let mut recycled = 0;
    for _ in 0..10 {
        w.step(1.0 / 60.0, 4);
        assert!(w.bodies.sims.iter().all(|s| s.fast));
        assert_eq!(w.profile().touching, 1);
        recycled += w.profile().recycled;
    }
    // The first step makes the manifold and the second finds the boxes fast for the first time.
    assert!(recycled >= 8, "{recycled} of 10 steps recycled");

    let mut w = World::new(StepSettings::default());
    w.create_body(
        &BodyDef::new(ShapeDef::Box {
            half_extents: [50.0, 0.5],
            radius: 0.0,
        })
        .kind(BodyKind::Static)
        .friction(0.0),
    )
    .unwrap();
    w.create_body(
        &BodyDef::new(ShapeDef::Box {
            half_extents: [0.02, 0.02],
            radius: 0.0,
        })
        .at(0.0, 0.52)
        .velocity(1.2, 0.0)
        .friction(0.0),
    )
    .unwrap();
    for _ in 0..10 {
        w.step(1.0 / 60.0, 4);
        assert!(w.bodies.sims[1].fast);
        assert_eq!(w.profile().touching, 1);
        assert_eq!(w.profile().recycled, 0);
    }
}

/// A recycled manifold covers only the closing it was made for (its speculative margin grows
/// with the pair's closing speed; `ContactCache::closing_reach`). Two 1 m boxes flying side by side at 30 m/s, 3 cm apart, without gravity:
/// their contact has no point (the gap is past the 2 cm speculative distance and they do not
/// close) and is recycled step after step. Then B is turned towards A at 6 m/s relative
/// (10 cm a step): the contact must be made again at once, with a speculative point, or B
/// would sink 7 cm into A before the pair moved far enough to be recomputed.
#[test]
fn a_fast_pair_that_starts_closing_is_not_recycled() {
    let mut w = flying_pair([1.03, 0.0]);
    let mut recycled = 0;
    for _ in 0..5 {
        w.step(1.0 / 60.0, 4);
        assert_eq!((w.contact_count(), w.profile().touching), (1, 0));
        recycled += w.profile().recycled;
    }
    assert!(
        recycled >= 3,
        "only {recycled} of 5 steps recycled the contact"
    );
    w.set_velocity(BodyId::scene(1), Vec2::new(24.0, 0.0), 0.0)
        .unwrap();
    w.step(1.0 / 60.0, 4);
    assert_eq!((w.profile().recycled, w.profile().touching), (0, 1));
    for _ in 0..10 {
        let gap = w.body_view(1).position.x - w.body_view(0).position.x - 1.0;
        // 1 cm: twice Box2D's linear slop, the overlap soft contacts leave.
        assert!(gap > -0.01, "B sank {} m into A", -gap);
        w.step(1.0 / 60.0, 4);
    }
}

/// A manifold that left out a point (not approaching when it was made) still covers every
/// closing distance in a step too short to bring that point within the speculative distance
/// (`step::recycle`). Two 1 m boxes flying side by side at 30 m/s, 2.2 cm apart, B sliding
/// along A's face at 0.6 m/s: the closing bound (1 cm a step) reaches the face points, but
/// they do not approach and are dropped; the manifold covers closing by less than about
/// (2.2 - 2) cm a step (a little less for the lever of the anchors, midway across the gap).
/// At 0.06 m/s (0.1 cm a step) it is kept. When B turns towards A at 0.3 m/s it must be made
/// again, with its points: the recycling distance does not decide it, B having slid 1.1 cm
/// of the 2 cm an empty manifold allows.
#[test]
fn a_manifold_that_dropped_a_point_is_recycled_only_below_that_points_reach() {
    let start = || {
        let mut w = flying_pair([1.022, 0.0]);
        w.set_velocity(BodyId::scene(1), Vec2::new(30.0, 0.6), 0.0)
            .unwrap();
        w.step(1.0 / 60.0, 4);
        assert_eq!((w.contact_count(), w.profile().touching), (1, 0));
        w.set_velocity(BodyId::scene(1), Vec2::new(30.0, 0.06), 0.0)
            .unwrap();
        w
    };
    let mut w = start();
    w.step(1.0 / 60.0, 4);
    assert!(w.bodies.sims.iter().all(|s| s.fast));
    assert_eq!((w.profile().recycled, w.profile().touching), (1, 0));
    w.set_velocity(BodyId::scene(1), Vec2::new(29.7, 0.06), 0.0)
        .unwrap();
    w.step(1.0 / 60.0, 4);
    assert_eq!((w.profile().recycled, w.profile().touching), (0, 1));
    // The reach is a distance: the same 0.06 m/s over a step four times as long closes
    // 0.4 cm, past it, so the manifold is made again (a bound on speed alone kept it).
    let mut w = start();
    w.step(4.0 / 60.0, 4);
    assert_eq!(w.profile().recycled, 0);
}

/// A motor's most torque or force set below zero or to NaN between steps (through
/// `joint_kind_mut`, which does not check it) steps without a panic (`f32::clamp` panics on
/// such a bound; `math::clamp_within` does not), and leaves the world finite.
#[test]
fn a_motor_given_a_bad_torque_at_run_time_does_not_panic() {
    for (bad, simd) in [
        (-1.0, false),
        (f32::NAN, false),
        (-1.0, true),
        (f32::NAN, true),
    ] {
        let mut w = hinge_net(false);
        w.settings_mut().simd = simd;
        let ids: Vec<_> = w.joint_ids().collect();
        for &id in &ids {
            if let JointKind::Revolute(r) = w.joint_kind_mut(id).unwrap() {
                r.motor = Some(AngularMotor {
                    speed: 1.0,
                    max_torque: bad,
                });
            }
        }
        for _ in 0..5 {
            w.step(1.0 / 60.0, 4);
        }
        assert_eq!(w.joint_count(), ids.len());
        assert!((0..w.body_count()).all(|b| w.body_view(b).position.is_finite()));
    }
}

/// Every call that names a body, shape or joint refuses a stale id with `NoBody`,
/// `NoShape` or `NoJoint`, changes nothing, and never reaches the object that took the slot
/// next (CONTRACT.md section 8: one handle per object).
#[test]
fn a_stale_id_is_refused_by_every_call_and_never_names_the_slots_next_holder() {
    let mut w = ball_on_ground();
    let ground = BodyId::scene(0);
    let ball = BodyId::scene(1);
    let joint = w
        .create_joint(&JointDef::hinge([ground, ball], [0.0, 1.0]))
        .unwrap();
    let shape = w.body_shapes(ball).unwrap().next().unwrap().id;
    w.destroy_joint(joint).unwrap();
    w.destroy_body(ball).unwrap();
    // The slot's next body: the stale id must not reach it.
    let next = w
        .create_body(&BodyDef::new(ShapeDef::Circle { radius: 0.25 }).at(2.0, 3.0))
        .unwrap();
    assert_eq!(next.index, ball.index);
    assert_ne!(next, ball);
    let next_joint = w
        .create_joint(&JointDef::hinge([ground, next], [2.0, 3.0]))
        .unwrap();
    assert_eq!(next_joint.index, joint.index);
    let next_shape = w.body_shapes(next).unwrap().next().unwrap().id;
    assert_eq!(next_shape.index, shape.index);
    w.step(1.0 / 60.0, 4);
    let hash = w.state_hash();
    let before = w.body(next).unwrap();

    let no_body = Err(WorldError::NoBody(ball));
    assert_eq!(w.body(ball).map(|_| ()), no_body);
    assert_eq!(w.mass(ball).map(|_| ()), no_body);
    assert_eq!(w.inertia(ball).map(|_| ()), no_body);
    assert_eq!(w.local_center(ball).map(|_| ()), no_body);
    assert_eq!(w.is_awake(ball).map(|_| ()), no_body);
    assert_eq!(w.is_bullet(ball).map(|_| ()), no_body);
    assert_eq!(w.island_of(ball).map(|_| ()), no_body);
    assert_eq!(w.user_data(ball).map(|_| ()), no_body);
    assert!(matches!(w.body_shapes(ball), Err(WorldError::NoBody(b)) if b == ball));
    assert!(!w.contains_body(ball) && w.contains_body(next));
    let (v, p) = (Vec2::new(1.0, 2.0), Vec2::new(2.0, 3.0));
    assert_eq!(w.set_velocity(ball, v, 1.0), no_body);
    assert_eq!(w.apply_linear_impulse(ball, v, p, true), no_body);
    assert_eq!(w.apply_linear_impulse_to_center(ball, v, true), no_body);
    assert_eq!(w.apply_angular_impulse(ball, 1.0, true), no_body);
    assert_eq!(w.set_transform(ball, p, 1.0), no_body);
    assert_eq!(w.set_target_transform(ball, p, 1.0, 1.0 / 60.0), no_body);
    assert_eq!(w.set_kind(ball, BodyKind::Static), no_body);
    assert_eq!(w.set_bullet(ball, true), no_body);
    assert_eq!(w.set_user_data(ball, 7), no_body);
    let part = crate::def::PartDef::new(ShapeDef::Circle { radius: 0.1 });
    assert_eq!(w.create_shape(ball, &part).map(|_| ()), no_body);
    assert_eq!(
        w.create_joint(&JointDef::hinge([ground, ball], [0.0, 1.0]))
            .map(|_| ()),
        no_body
    );
    assert_eq!(
        w.create_mouse_joint(ball, p, 5.0, 0.7, 100.0).map(|_| ()),
        no_body
    );
    assert_eq!(w.apply_force(ball, v, p, true), no_body);
    assert_eq!(w.apply_force_to_center(ball, v, true), no_body);
    assert_eq!(w.apply_torque(ball, 1.0, true), no_body);
    assert_eq!(w.applied_force(ball).map(|_| ()), no_body);
    assert_eq!(w.set_linear_damping(ball, 0.5), no_body);
    assert_eq!(w.linear_damping(ball).map(|_| ()), no_body);
    assert_eq!(w.set_angular_damping(ball, 0.5), no_body);
    assert_eq!(w.angular_damping(ball).map(|_| ()), no_body);
    assert_eq!(w.set_gravity_scale(ball, 0.5), no_body);
    assert_eq!(w.gravity_scale(ball).map(|_| ()), no_body);
    assert_eq!(w.set_fixed_rotation(ball, true), no_body);
    assert_eq!(w.fixed_rotation(ball).map(|_| ()), no_body);
    assert_eq!(w.set_sleep_enabled(ball, false), no_body);
    assert_eq!(w.sleep_enabled(ball).map(|_| ()), no_body);
    assert_eq!(w.set_awake(ball, false), no_body);
    let md = crate::shape::MassData {
        mass: 1.0,
        center: Vec2::ZERO,
        inertia: 1.0,
    };
    assert_eq!(w.set_mass_data(ball, md), no_body);
    assert_eq!(w.mass_data(ball).map(|_| ()), no_body);
    assert_eq!(w.body_contacts(ball).map(|_| ()), no_body);
    assert_eq!(w.body_joints(ball).map(|_| ()), no_body);
    assert_eq!(w.destroy_body(ball), no_body);
    assert_eq!(w.destroy_bodies(&[next, ball]), no_body);

    let no_shape = Err(WorldError::NoShape(shape));
    assert_eq!(w.shape(shape).map(|_| ()), no_shape);
    assert!(!w.contains_shape(shape) && w.contains_shape(next_shape));
    assert_eq!(w.set_friction(shape, 0.5), no_shape);
    assert_eq!(w.friction(shape).map(|_| ()), no_shape);
    assert_eq!(w.set_restitution(shape, 0.5), no_shape);
    assert_eq!(w.restitution(shape).map(|_| ()), no_shape);
    assert_eq!(w.set_density(shape, 2.0), no_shape);
    assert_eq!(w.density(shape).map(|_| ()), no_shape);
    assert_eq!(w.set_filter(shape, crate::def::Filter::default()), no_shape);
    assert_eq!(w.filter(shape).map(|_| ()), no_shape);
    assert_eq!(w.set_shape_user_data(shape, 7), no_shape);
    assert_eq!(w.shape_user_data(shape).map(|_| ()), no_shape);
    assert_eq!(w.shape_contacts(shape).map(|_| ()), no_shape);
    assert_eq!(w.sensor_overlaps(shape).map(|_| ()), no_shape);
    assert_eq!(w.destroy_shape(shape), no_shape);

    let no_joint = Err(WorldError::NoJoint(joint));
    assert_eq!(w.joint(joint).map(|_| ()), no_joint);
    assert_eq!(w.joint_bodies(joint).map(|_| ()), no_joint);
    assert_eq!(w.joint_reaction(joint).map(|_| ()), no_joint);
    assert_eq!(w.joint_anchors(joint).map(|_| ()), no_joint);
    assert_eq!(w.joint_kind_mut(joint).map(|_| ()), no_joint);
    assert_eq!(w.set_mouse_target(joint, p), no_joint);
    assert_eq!(w.destroy_joint(joint), no_joint);

    // Nothing changed: the slot's new holders are as they were.
    assert_eq!(w.state_hash(), hash);
    assert_eq!(w.body(next).unwrap(), before);
    assert_eq!(w.body_count(), 2);
    assert_eq!(w.joint_bodies(next_joint), Ok([ground, next]));
    assert_eq!(w.shape(next_shape).unwrap().body, next);
    w.validate().unwrap();
}

/// Box2D's impulse rule (`b2Body_ApplyLinearImpulse`): with `wake` a sleeping body wakes and
/// takes the impulse; without, it is left as it is. Non-finite input is refused, unchanged.
#[test]
fn impulses_wake_only_when_asked_and_refuse_non_finite_input() {
    let mut w = ball_on_ground();
    let ball = BodyId::scene(1);
    for _ in 0..240 {
        w.step(1.0 / 60.0, 4);
    }
    assert_eq!(w.is_awake(ball), Ok(false), "the ball should sleep by now");
    let asleep = w.body(ball).unwrap();
    let j = Vec2::new(2.0, 0.0);
    w.apply_linear_impulse_to_center(ball, j, false).unwrap();
    w.apply_angular_impulse(ball, 1.0, false).unwrap();
    w.apply_linear_impulse(ball, j, asleep.position + Vec2::Y, false)
        .unwrap();
    assert_eq!(w.body(ball).unwrap(), asleep);
    // Refused whole: the valid parts of a bad call change nothing either.
    let nan = Vec2::new(f32::NAN, 0.0);
    assert!(matches!(
        w.apply_linear_impulse_to_center(ball, nan, true),
        Err(WorldError::Invalid { .. })
    ));
    assert!(w.apply_linear_impulse(ball, j, nan, true).is_err());
    assert!(w.apply_angular_impulse(ball, f32::INFINITY, true).is_err());
    assert_eq!(w.body(ball).unwrap(), asleep);
    // Woken, it takes each impulse by its inverse mass or inertia (1e-6 relative: f32).
    let (m, i) = (w.mass(ball).unwrap(), w.inertia(ball).unwrap());
    w.apply_linear_impulse_to_center(ball, j, true).unwrap();
    let b = w.body(ball).unwrap();
    assert!(b.awake);
    assert!((b.linear_velocity.x * m / 2.0 - 1.0).abs() < 1e-6, "{b:?}");
    assert_eq!(b.angular_velocity, asleep.angular_velocity);
    w.apply_angular_impulse(ball, 0.5, true).unwrap();
    let w1 = w.body(ball).unwrap().angular_velocity;
    assert!(
        ((w1 - asleep.angular_velocity) * i / 0.5 - 1.0).abs() < 1e-6,
        "{w1}"
    );
    // A static body takes nothing.
    let ground = BodyId::scene(0);
    w.apply_linear_impulse_to_center(ground, j, true).unwrap();
    assert_eq!(w.body(ground).unwrap().linear_velocity, Vec2::ZERO);
}

/// A box at rest on a frictionless kinematic platform that slides under it stays awake (the
/// touch update keeps what a moving kinematic body touches awake, walking the narrow phase's
/// one-sided marks: the box itself does not move), the same box on a static floor falls
/// asleep, and every mark is drained within its step: a
/// mark left set is caught by `validate`.
#[test]
fn a_moving_kinematic_platform_keeps_its_load_awake_and_no_mark_outlives_its_step() {
    let rider = |kind: BodyKind| {
        let mut w = World::new(StepSettings::default());
        w.create_body(
            &BodyDef::new(ShapeDef::Box {
                half_extents: [20.0, 0.5],
                radius: 0.0,
            })
            .kind(kind)
            .friction(0.0)
            .velocity(
                if kind == BodyKind::Kinematic {
                    0.5
                } else {
                    0.0
                },
                0.0,
            ),
        )
        .unwrap();
        let load = w
            .create_body(
                &BodyDef::new(ShapeDef::Box {
                    half_extents: [0.5, 0.5],
                    radius: 0.0,
                })
                .friction(0.0)
                .at(0.0, 1.0),
            )
            .unwrap();
        for step in 0..240 {
            w.step(1.0 / 60.0, 4);
            if let Err(e) = w.validate() {
                panic!("{kind:?}, step {step}: {e}");
            }
        }
        (w, load)
    };
    // Box2D's time to sleep is 0.5 s: 240 steps are 4 s.
    let (still, load) = rider(BodyKind::Static);
    let (w, moved) = rider(BodyKind::Kinematic);
    assert!(
        !still.is_awake(load).unwrap(),
        "on a static floor it sleeps"
    );
    assert!(
        w.is_awake(moved).unwrap(),
        "on a moving platform it stays awake"
    );
    let v = w.body(moved).unwrap().linear_velocity;
    assert!(
        v.x.abs() < 1e-3,
        "frictionless: the platform slides under it ({v})"
    );
    // A mark left set (as a touch update that missed it would leave it) is refused.
    super::stores::mark(&w.contacts.one_sided, 0);
    assert!(w.validate().unwrap_err().contains("one-sided"));
}

/// A box sliding up beside a static wall, 1 cm from it (within the speculative distance, so
/// the pair has a contact), without gravity: its boxes move every step or two while the
/// pair's boxes keep overlapping. Returns the world and both shapes' slots.
fn box_sliding_beside_a_wall() -> (World, ShapeId, ShapeId) {
    let mut w = World::new(StepSettings {
        gravity: Vec2::ZERO,
        enable_sleep: false,
        ..StepSettings::default()
    });
    let wall = w
        .create_body(
            &BodyDef::new(ShapeDef::Box {
                half_extents: [0.5, 5.0],
                radius: 0.0,
            })
            .kind(BodyKind::Static)
            .at(1.01, 0.0),
        )
        .unwrap();
    let slider = w
        .create_body(
            &BodyDef::new(ShapeDef::Box {
                half_extents: [0.5, 0.5],
                radius: 0.0,
            })
            .at(0.0, -2.0),
        )
        .unwrap();
    w.set_velocity(slider, Vec2::new(0.0, 2.0), 0.0).unwrap();
    let shape = |w: &World, b| w.body_shapes(b).unwrap().next().unwrap().id;
    let (a, b) = (shape(&w, slider), shape(&w, wall));
    (w, a, b)
}

fn have_contact(w: &World, a: ShapeId, b: ShapeId) -> bool {
    w.contacts.pairs.contains_key(&pair_key(a.index, b.index))
}

#[test]
fn a_pair_refused_by_a_custom_filter_is_found_once_the_filter_is_gone() {
    // The pair search skips a pair whose boxes overlapped at its last search: the custom
    // filter's refusal then must not count as "searched" once the filter is removed.
    let (mut w, a, b) = box_sliding_beside_a_wall();
    w.set_custom_filter(Some(Box::new(|_, _| false)));
    for _ in 0..10 {
        w.step(1.0 / 60.0, 4);
    }
    assert!(!have_contact(&w, a, b));
    w.set_custom_filter(None);
    for _ in 0..10 {
        w.step(1.0 / 60.0, 4);
    }
    assert!(have_contact(&w, a, b), "the pair was not found again");
}

#[test]
fn a_pair_whose_filter_refused_then_allows_it_is_found_again_while_its_boxes_overlap() {
    // A filter change between steps, the boxes unchanged: the pair search must look the pair
    // up again rather than skip it as searched, both where the change removed the pair's
    // contact and where the pair never had one (nothing was removed).
    let never = Filter {
        mask: 0,
        ..Filter::default()
    };
    let step = |w: &mut World, n| (0..n).for_each(|_| w.step(1.0 / 60.0, 4));
    for refused_from_the_start in [false, true] {
        let (mut w, a, b) = box_sliding_beside_a_wall();
        if !refused_from_the_start {
            step(&mut w, 5);
            assert!(have_contact(&w, a, b));
        }
        w.set_filter(a, never).unwrap();
        step(&mut w, 5);
        assert!(!have_contact(&w, a, b));
        w.set_filter(a, Filter::default()).unwrap();
        w.step(1.0 / 60.0, 4);
        assert!(have_contact(&w, a, b), "the pair was not found again");
    }
}
