//! Continuous collision (Box2D v3's `b2SolveContinuous`, in `solver.c`): a dynamic body that
//! moved more than half its thickness in a step (finalize marks it `fast`) is swept from its
//! pose at the start of the step to its pose at the end against the static shapes in its
//! way, and put back at the first time of impact, keeping its velocity; the next step's
//! speculative contact then stops it at the surface. A bullet is swept against kinematic and
//! other dynamic bodies too (at their poses after the step). However fast, thin or spinning a
//! body is, it cannot pass through a static shape: the sweep covers the whole step.
//!
//! Each fast body reads only shapes that do not move in this stage and writes only its own
//! pose, so the result does not depend on the order or the thread; bullets come after every
//! other body has been swept, and read their final poses.

use super::World;
use super::query::QueryFilter;
use crate::collision::distance::{Impact, Proxy, Sweep, time_of_impact};
use crate::def::BodyKind;
use crate::math::{Transform, cross};
use crate::shape::{Aabb, Shape};
use crate::threads::parallel::{Spread, for_each_part};

impl World {
    /// Sweeps each fast body of `fast` (slots; their poses at the step's start are in
    /// `sweep_starts`) that is a bullet or not, as `bullets` says, and moves it back to its
    /// first time of impact. Returns how many it moved back.
    ///
    /// The sweeps run over `spread` (Box2D sweeps each fast body in its finalize task): each
    /// reads only what no sweep of this pass writes (static shapes; for a bullet, the final
    /// poses of bodies that are not bullets) and writes its time of impact into its own slot;
    /// the poses are moved back after, in slot order.
    pub(super) fn solve_continuous(
        &mut self,
        fast: &[u32],
        bullets: bool,
        spread: Spread<'_>,
    ) -> usize {
        if !bullets && self.shapes.static_tree_stale {
            let (slots, sims, records) =
                (&self.shapes.slots, &self.bodies.sims, &self.shapes.records);
            self.shapes
                .static_tree
                .rebuild(&self.shapes.swept_boxes, |s| {
                    slots.is_alive(s as usize)
                        && !records[s as usize].disabled
                        && sims[records[s as usize].body as usize].kind == BodyKind::Static
                });
            self.shapes.static_tree_stale = false;
        }
        let mut impacts = std::mem::take(&mut self.sweeps.impacts);
        impacts.clear();
        impacts.resize(fast.len(), 1.0);
        {
            let world = &*self;
            let sweep_part = |_: usize, (times, bodies): (&mut [f32], &[u32])| {
                for (t, &b) in times.iter_mut().zip(bodies) {
                    if world.bodies.records[b as usize].bullet == bullets {
                        *t = world.first_impact(b, &world.sweep_of(b), bullets);
                    }
                }
            };
            for_each_part(
                spread,
                (&mut impacts[..], fast),
                self.wide.finalize,
                &sweep_part,
            );
        }
        let mut rewound = 0;
        for (&t, &b) in impacts.iter().zip(fast) {
            if t < 1.0 {
                self.bodies.sims[b as usize].xf = self.sweep_of(b).at(t);
                rewound += 1;
            }
        }
        self.sweeps.impacts = impacts;
        rewound
    }

    /// Body `b`'s motion over the step: from its pose at the start to its pose now.
    fn sweep_of(&self, b: u32) -> Sweep {
        let (start, end) = (
            self.sweeps.starts[b as usize],
            self.bodies.sims[b as usize].xf,
        );
        Sweep {
            c0: start.p,
            c1: end.p,
            q0: start.q,
            q1: end.q,
        }
    }

    /// The first time of impact (a fraction of the step; 1 for none) of body `b` moving by
    /// `sweep` with the shapes it may not pass: static ones, and for a bullet kinematic and
    /// dynamic ones that are not bullets. Candidates are taken in the tree's order as the
    /// query finds them (each sweep is bounded by the best time so far).
    fn first_impact(&self, b: u32, sweep: &Sweep, bullet: bool) -> f32 {
        let body = b as usize;
        // The box every shape of the body passes through in the step.
        let mut swept: Option<Aabb> = None;
        for s in self.shapes_of_body(body) {
            let r = &self.shapes.records[s as usize];
            if r.sensor {
                continue;
            }
            let shape = &self.shapes.geometry[s as usize];
            let at = |xf: Transform| shape.aabb(r.pose(xf));
            let both = at(sweep.at(0.0)).union(&at(sweep.at(1.0)));
            swept = Some(swept.map_or(both, |b| b.union(&both)));
        }
        let Some(swept) = swept else {
            return 1.0;
        };
        let min_extent = self.bodies.sims[body].min_extent;
        let mut best = 1.0f32;
        let mut against = |o: u32| {
            let ro = &self.shapes.records[o as usize];
            let other = ro.body as usize;
            let kind = self.bodies.sims[other].kind;
            let blocks = match kind {
                BodyKind::Static => true,
                _ => bullet && !self.bodies.records[other].bullet,
            };
            if other == body || !blocks || ro.sensor {
                return;
            }
            if !self.joints.no_collide.is_empty()
                && self
                    .joints
                    .no_collide
                    .contains_key(&super::pair_key(b, ro.body))
            {
                return;
            }
            let other_pose = self.bodies.sims[other].xf;
            let other_proxy = Proxy::of(&self.shapes.geometry[o as usize], ro.from_center);
            let other_sweep = Sweep::still(other_pose);
            for s in self.shapes_of_body(body) {
                let r = &self.shapes.records[s as usize];
                if r.sensor || !r.filter.should_collide(&ro.filter) {
                    continue;
                }
                let shape = &self.shapes.geometry[s as usize];
                let centroid = r
                    .from_center
                    .apply(shape.aabb(Transform::IDENTITY).center());
                if let Shape::ChainSegment(c) = &self.shapes.geometry[o as usize] {
                    // A chain pushes only from its front: sweep only a shape whose centre
                    // crosses it from front to back (Box2D's rule, so that a body sliding
                    // along a chain, or leaving it from behind, is not held back).
                    let xf = ro.pose(other_pose);
                    let (p1, p2) = (xf.apply(c.segment.point1), xf.apply(c.segment.point2));
                    let e = p2 - p1;
                    let before = cross(sweep.at(0.0).apply(centroid) - p1, e);
                    let after = cross(sweep.at(1.0).apply(centroid) - p1, e);
                    if before < 0.0 || after > 0.0 || before == after {
                        continue;
                    }
                }
                let proxy = Proxy::of(shape, r.from_center);
                let mut impact = time_of_impact(&other_proxy, &other_sweep, &proxy, sweep, best);
                if impact == Impact::Overlapping {
                    // Touching already at the start (resting on the ground, sliding along a
                    // wall): sweep a small disc about the shape's centre instead, which meets
                    // the other only if the shape is really going through it (Box2D's
                    // fallback).
                    let core = Proxy::points(&[centroid], 0.25 * min_extent, Transform::IDENTITY);
                    impact = time_of_impact(&other_proxy, &other_sweep, &core, sweep, best);
                }
                if let Impact::At(t) = impact
                    && t < best
                {
                    best = t;
                }
            }
        };
        if bullet {
            self.shapes_in_box(&swept, &QueryFilter::ALL, |o| {
                against(o);
                true
            });
        } else {
            // Only static shapes stop a body that is not a bullet: their own tree, not the
            // one of every shape (a pile of falling boxes would find each other).
            self.shapes
                .static_tree
                .query(&swept, &self.shapes.swept_boxes, against);
        }
        best
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::def::{BodyDef, ShapeDef};
    use crate::id::BodyId;
    use crate::world::StepSettings;
    use glam::Vec2;

    const DT: f32 = 1.0 / 60.0;

    /// A static wall 5 cm thick from y = -5 to 5 at x = 10, and `projectile` at the origin
    /// flying at `speed` m/s towards it, without gravity.
    fn shot(projectile: BodyDef, speed: f32, continuous: bool) -> (World, BodyId) {
        let mut w = World::new(StepSettings {
            gravity: Vec2::ZERO,
            continuous,
            ..StepSettings::default()
        });
        w.create_body(
            &BodyDef::new(ShapeDef::Box {
                half_extents: [0.025, 5.0],
                radius: 0.0,
            })
            .kind(BodyKind::Static)
            .at(10.0, 0.0),
        )
        .unwrap();
        let b = w.create_body(&projectile.velocity(speed, 0.0)).unwrap();
        (w, b)
    }

    /// The largest x any point of the body reached over `steps` steps.
    fn farthest_point(w: &mut World, b: BodyId, steps: usize) -> f32 {
        (0..steps)
            .map(|_| {
                w.step(DT, 4);
                w.validate().unwrap();
                w.body_shapes(b)
                    .unwrap()
                    .map(|v| v.shape.aabb(v.transform).max.x)
                    .fold(f32::MIN, f32::max)
            })
            .fold(f32::MIN, f32::max)
    }

    /// The wall's near and far faces.
    const FACE: f32 = 9.975;
    const FAR_FACE: f32 = 10.025;

    #[test]
    fn a_fast_small_disc_never_passes_a_thin_wall() {
        let disc = BodyDef::new(ShapeDef::Circle { radius: 0.05 });
        for speed in [30.0, 120.0, 300.0, 399.0] {
            let (mut w, b) = shot(disc.clone(), speed, true);
            let x = farthest_point(&mut w, b, 60);
            assert!(x <= FACE + crate::LINEAR_SLOP, "{speed} m/s: reached {x}");
            assert!(x > 9.5, "{speed} m/s: it never got near the wall ({x})");
        }
    }

    #[test]
    fn fast_spinning_thin_bodies_never_pass_a_thin_wall_and_do_without_sweeping() {
        // A capsule 1 m long and 6 cm thick, and a plate 4 cm thick, at 300 m/s (5 m a step)
        // turning fast: the speculative contact, made from the pose at the step's start,
        // misses the face the turn brings round, and without the sweep they go through.
        let capsule = BodyDef::new(ShapeDef::Capsule {
            center1: [-0.5, 0.0],
            center2: [0.5, 0.0],
            radius: 0.03,
        })
        .spin(60.0);
        let plate = BodyDef::new(ShapeDef::Box {
            half_extents: [0.02, 0.5],
            radius: 0.0,
        })
        .spin(60.0);
        for (name, body) in [("capsule", capsule), ("plate", plate)] {
            let (mut w, b) = shot(body.clone(), 300.0, false);
            let (centre, _) = centre_and_end(&mut w, b, 60);
            assert!(
                centre > FAR_FACE,
                "{name} without sweeping: held; the test shows nothing"
            );
            // Swept, its centre stops at the wall. A tip turning into the wall once they
            // touch is the contact's to push out (as in Box2D, the sweep does not hold back a
            // body already touching: a body sliding or rolling along a wall must not stick),
            // so it may dig in for a few steps; then it is pushed back out.
            let (mut w, b) = shot(body, 300.0, true);
            let (centre, end) = centre_and_end(&mut w, b, 60);
            assert!(centre < FACE, "{name}: its centre reached {centre}");
            assert!(
                centre > FACE - 0.6,
                "{name}: it never got to the wall ({centre})"
            );
            assert!(
                end <= FACE + crate::LINEAR_SLOP,
                "{name}: it ends at {end}, in the wall"
            );
        }
    }

    /// The largest x the body's centre reached over `steps` steps, and the largest x of any
    /// point of it after the last.
    fn centre_and_end(w: &mut World, b: BodyId, steps: usize) -> (f32, f32) {
        let mut centre = f32::MIN;
        for _ in 0..steps {
            w.step(DT, 4);
            w.validate().unwrap();
            centre = centre.max(w.body_view(b.index as usize).position.x);
        }
        let end = w
            .body_shapes(b)
            .unwrap()
            .map(|v| v.shape.aabb(v.transform).max.x)
            .fold(f32::MIN, f32::max);
        (centre, end)
    }

    #[test]
    fn a_fast_spinning_bullet_never_passes_a_thin_free_plank_and_a_plain_body_does() {
        // A heavy plank 5 cm thick, free to move, in the way of the spinning capsule above
        // at 300 m/s: a bullet is swept against it, a plain body only against static shapes.
        let run = |bullet: bool, continuous: bool| {
            let mut w = World::new(StepSettings {
                gravity: Vec2::ZERO,
                continuous,
                ..StepSettings::default()
            });
            let plank = w
                .create_body(
                    &BodyDef::new(ShapeDef::Box {
                        half_extents: [0.025, 5.0],
                        radius: 0.0,
                    })
                    .density(1000.0)
                    .at(10.0, 0.0),
                )
                .unwrap();
            let b = w
                .create_body(
                    &BodyDef::new(ShapeDef::Capsule {
                        center1: [-0.5, 0.0],
                        center2: [0.5, 0.0],
                        radius: 0.03,
                    })
                    .spin(60.0)
                    .bullet(bullet)
                    .velocity(300.0, 0.0),
                )
                .unwrap();
            for _ in 0..30 {
                w.step(DT, 4);
                w.validate().unwrap();
                // Through: its centre past the plank's.
                let (x, plank_x) = (
                    w.body_view(b.index as usize).position.x,
                    w.body_view(plank.index as usize).position.x,
                );
                if x > plank_x {
                    return false;
                }
            }
            true
        };
        assert!(run(true, true), "the bullet went through");
        assert!(
            !run(false, true),
            "a plain body was held: the test shows nothing"
        );
        assert!(
            !run(true, false),
            "held without sweeping: the test shows nothing"
        );
    }

    #[test]
    fn a_wall_made_moved_or_turned_static_between_steps_is_swept_against() {
        // The spinning capsule that passes a 5 cm wall unswept, shot at walls that appear
        // after the static shapes' tree was first built.
        let capsule = BodyDef::new(ShapeDef::Capsule {
            center1: [-0.5, 0.0],
            center2: [0.5, 0.0],
            radius: 0.03,
        })
        .spin(60.0);
        let wall = |x: f32, kind: BodyKind| {
            BodyDef::new(ShapeDef::Box {
                half_extents: [0.025, 5.0],
                radius: 0.0,
            })
            .kind(kind)
            .at(x, 0.0)
        };
        for case in ["made", "moved", "turned static"] {
            let (mut w, b) = shot(capsule.clone(), 300.0, true);
            // The far wall at x = 10 is swept against from the first step.
            w.step(DT, 4);
            // The wall at x = 10 goes (destroyed, or moved to 20); one stands at x = 20.
            let first = BodyId::scene(0);
            match case {
                "made" => {
                    w.destroy_body(first).unwrap();
                    w.create_body(&wall(20.0, BodyKind::Static)).unwrap();
                }
                "moved" => {
                    w.set_transform(first, Vec2::new(20.0, 0.0), 0.0).unwrap();
                }
                _ => {
                    w.destroy_body(first).unwrap();
                    let plank = w.create_body(&wall(20.0, BodyKind::Dynamic)).unwrap();
                    w.step(DT, 4);
                    w.set_kind(plank, BodyKind::Static).unwrap();
                }
            }
            let mut centre = f32::MIN;
            for _ in 0..60 {
                w.step(DT, 4);
                centre = centre.max(w.body_view(b.index as usize).position.x);
            }
            assert!(
                centre > 15.0,
                "{case}: the capsule stopped short, at {centre}"
            );
            assert!(
                centre < 19.975,
                "{case}: the capsule's centre reached {centre}"
            );
        }
    }

    /// A volley of 48 fast bodies (discs, boxes and spinning capsules, every fourth a
    /// bullet) at a thin wall with a free plank before it, swept on one worker and split over
    /// three (each sweep writes its own slot, the poses are moved back after): the same bits
    /// every step, and the sweeps did hold bodies back.
    #[test]
    fn sweeps_split_over_workers_give_the_same_bits() {
        let run = |workers: usize| {
            let (mut w, _) = shot(BodyDef::new(ShapeDef::Circle { radius: 0.05 }), 0.0, true);
            w.set_workers_beyond_cores(true);
            w.set_wide_thresholds(crate::world::WideThresholds::ALWAYS);
            w.set_thread_count(workers);
            w.create_body(
                &BodyDef::new(ShapeDef::Box {
                    half_extents: [0.025, 2.0],
                    radius: 0.0,
                })
                .at(8.0, 0.0)
                .density(50.0),
            )
            .unwrap();
            for i in 0..48 {
                let shape = match i % 3 {
                    0 => ShapeDef::Circle { radius: 0.04 },
                    1 => ShapeDef::Box {
                        half_extents: [0.03, 0.06],
                        radius: 0.0,
                    },
                    _ => ShapeDef::Capsule {
                        center1: [-0.2, 0.0],
                        center2: [0.2, 0.0],
                        radius: 0.02,
                    },
                };
                let y = -4.5 + 0.19 * i as f32;
                let body = BodyDef::new(shape)
                    .at(-0.1 * (i % 5) as f32, y)
                    .velocity(150.0 + 5.0 * i as f32, 0.3 * (i % 7) as f32)
                    .spin(if i % 3 == 2 { 40.0 } else { 0.0 })
                    .bullet(i % 4 == 0);
                w.create_body(&body).unwrap();
            }
            let mut hashes = Vec::new();
            let mut rewound = 0;
            for _ in 0..20 {
                w.step(DT, 4);
                hashes.push(w.state_hash());
                rewound += w.profile().rewound;
            }
            (hashes, rewound)
        };
        let (one, rewound) = run(1);
        assert!(rewound >= 48, "only {rewound} sweeps held a body back");
        assert_eq!(run(3), (one, rewound));
    }
}
