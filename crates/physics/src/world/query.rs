//! Queries between steps: ray casts, and the shapes overlapping a box, a point or a shape, all
//! through the broad phase's tree (Box2D v3's `b2World_CastRay`, `b2World_OverlapAABB`,
//! `b2World_OverlapShape`; Rapier's `QueryPipeline`).
//!
//! The tree is refitted at the start of each step, so between steps it may lag the fat boxes
//! of the proxies that moved since: those (the `moved` list, usually a few) are tested one by
//! one, and skipped in the tree. After shapes were added or removed, until the next step
//! rebuilds the tree, a query tests every shape.

use glam::Vec2;

use super::World;
use super::events::ShapeRef;
use crate::collision::broad_phase::{BroadPhase, ray_may_cross};
use crate::collision::distance::{Impact, Proxy, Sweep, distance, time_of_impact};
use crate::collision::{Ray, ray_cast};
use crate::def::Filter;
use crate::id::BodyId;
use crate::math::Transform;
use crate::shape::{Aabb, Shape};

/// Which shapes a query sees (Box2D's `b2QueryFilter`): a shape is seen when its category is
/// in the query's `mask` and the query's `category` is in the shape's mask; sensors only
/// when `sensors` is set.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct QueryFilter {
    /// What the query is, as a shape's filter sees it.
    pub category: u64,
    /// The categories of shapes it sees.
    pub mask: u64,
    /// Whether it sees sensor shapes.
    pub sensors: bool,
    /// A body whose shapes it does not see (a character's own, when it casts from inside
    /// itself); Box2D has no such field and filters in the callback.
    pub exclude_body: Option<BodyId>,
}

impl Default for QueryFilter {
    /// Category 1 (a shape's default), every mask bit, no sensors.
    fn default() -> Self {
        QueryFilter {
            category: 1,
            mask: u64::MAX,
            sensors: false,
            exclude_body: None,
        }
    }
}

impl QueryFilter {
    /// Sees every shape, sensors too, even one whose own filter touches nothing (what a
    /// viewer's picking wants).
    pub const ALL: QueryFilter = QueryFilter {
        category: u64::MAX,
        mask: u64::MAX,
        sensors: true,
        exclude_body: None,
    };

    /// The same filter, not seeing `body`'s shapes.
    pub fn excluding(mut self, body: BodyId) -> QueryFilter {
        self.exclude_body = Some(body);
        self
    }

    fn sees(&self, filter: &Filter, sensor: bool) -> bool {
        if *self == QueryFilter::ALL {
            return true;
        }
        (self.sensors || !sensor)
            && (filter.category & self.mask) != 0
            && (self.category & filter.mask) != 0
    }
}

/// Where a ray met a shape.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayHit {
    /// The shape.
    pub shape: ShapeRef,
    /// The point, in the world.
    pub point: Vec2,
    /// The shape's outward normal there, in the world.
    pub normal: Vec2,
    /// How far along the ray: the point is `origin + fraction · translation`.
    pub fraction: f32,
}

/// Whether two shapes at these poses overlap or touch: the distance between their cores
/// (GJK) is within the sum of their radii plus `10 f32::EPSILON`, the bound Box2D's sensors
/// use (`sensor.c`, `b2SensorQueryCallback`, which tests by distance too). Every pair of
/// kinds is tested the same way, so a sensor sees a chain segment or a segment whatever the
/// other shape (the contact manifold routines, built for a speculative margin, found no
/// point for a thin box lying across a chain segment with a margin of 0).
pub(super) fn shapes_overlap(a: &Shape, pose_a: Transform, b: &Shape, pose_b: Transform) -> bool {
    let (pa, pb) = (
        Proxy::of(a, Transform::IDENTITY),
        Proxy::of(b, Transform::IDENTITY),
    );
    distance(&pa, pose_a, &pb, pose_b).distance < pa.radius + pb.radius + 10.0 * f32::EPSILON
}

/// Queries: ray casts, shape casts and overlaps through the broad phase, each result naming
/// its shape and body by id, filtered by a [`QueryFilter`].
///
/// ```
/// use tumble_physics::{BodyDef, BodyKind, QueryFilter, ShapeDef, StepSettings, Vec2, World};
///
/// let mut world = World::new(StepSettings::default());
/// let wall = world
///     .create_body(&BodyDef::new(ShapeDef::Box { half_extents: [0.5, 2.0], radius: 0.0 }).kind(BodyKind::Static).at(5.0, 0.0))
///     .unwrap();
/// let hit = world.cast_ray_closest(Vec2::ZERO, Vec2::new(10.0, 0.0), &QueryFilter::default()).unwrap();
/// assert_eq!(hit.shape.body, wall);
/// assert!((hit.point.x - 4.5).abs() < 1e-5 && hit.normal == Vec2::new(-1.0, 0.0));
/// ```
impl World {
    /// Whether the tree holds every live proxy (no shape added or removed since it was
    /// built).
    fn tree_holds_every_proxy(&self) -> bool {
        !self.shapes.proxies_changed
    }

    /// Whether shape slot `s` is live and `filter` sees it.
    fn seen(&self, s: u32, filter: &QueryFilter) -> bool {
        let r = &self.shapes.records[s as usize];
        let excluded = filter.exclude_body.is_some_and(|b| {
            b.index == r.body && b.generation == self.bodies.slots.generation(r.body as usize)
        });
        self.shapes.slots.is_alive(s as usize)
            && !r.disabled
            && !excluded
            && filter.sees(&r.filter, r.sensor)
    }

    /// Calls `f(shape slot)` for every shape `filter` sees whose fat box overlaps `aabb`,
    /// until it returns false.
    pub(super) fn shapes_in_box(
        &self,
        aabb: &Aabb,
        filter: &QueryFilter,
        mut f: impl FnMut(u32) -> bool,
    ) {
        let mut going = true;
        for s in self.untreed_after_tree(|tree| {
            tree.query(aabb, &self.shapes.swept_boxes, |s| {
                if going && !self.shapes.moved_flags[s as usize] && self.seen(s, filter) {
                    going = f(s);
                }
            });
        }) {
            if !going {
                return;
            }
            if self.shapes.swept_boxes[s as usize].overlaps(aabb) && self.seen(s, filter) {
                going = f(s);
            }
        }
    }

    /// The slots of the shapes `filter` sees whose fat boxes overlap `aabb`, ascending (so a
    /// query's results do not depend on the tree's shape).
    pub(super) fn shapes_in_box_sorted(&self, aabb: &Aabb, filter: &QueryFilter) -> Vec<u32> {
        let mut found = Vec::new();
        self.shapes_in_box(aabb, filter, |s| {
            found.push(s);
            true
        });
        found.sort_unstable();
        found
    }

    /// Walks the tree with `walk` when it holds every proxy, then gives the proxies a query
    /// must test one by one: those moved since the tree's refit (`walk` skips them), or every
    /// shape slot when shapes were added or removed since it was built (and `walk` is not
    /// called).
    fn untreed_after_tree(
        &self,
        walk: impl FnOnce(&BroadPhase),
    ) -> Box<dyn Iterator<Item = u32> + '_> {
        if self.tree_holds_every_proxy() {
            walk(&self.shapes.tree);
            Box::new(self.shapes.moved_proxies.iter().copied())
        } else {
            Box::new(0..self.shapes.geometry.len() as u32)
        }
    }

    /// Casts the ray `origin + t · translation`, t in [0, 1], against every shape `filter`
    /// sees, calling `f` with each hit the ray reaches (Box2D's `b2World_CastRay`): `f`
    /// returns the fraction to clip the ray to (its hit's `fraction` to find the nearest), 1
    /// to go on unclipped, 0 to stop, or a negative number to ignore this shape. Hits come in
    /// the tree's order, not the ray's; a ray that starts inside a shape with area does not
    /// hit it.
    pub fn cast_ray(
        &self,
        origin: Vec2,
        translation: Vec2,
        filter: &QueryFilter,
        mut f: impl FnMut(&RayHit) -> f32,
    ) {
        if !(origin.is_finite() && translation.is_finite()) {
            return;
        }
        let mut visit = |s: u32, max_fraction: f32| -> f32 {
            if !self.seen(s, filter) {
                return max_fraction;
            }
            let pose = self.shape_pose(s);
            let local = Ray {
                origin: pose.apply_inv(origin),
                translation: pose.q.apply_inv(translation),
                max_fraction,
            };
            let Some(hit) = ray_cast(&self.shapes.geometry[s as usize], &local) else {
                return max_fraction;
            };
            let value = f(&RayHit {
                shape: self.shape_ref(s),
                point: pose.apply(hit.point),
                normal: pose.q.apply(hit.normal),
                fraction: hit.fraction,
            });
            if value < 0.0 {
                max_fraction
            } else {
                value.min(max_fraction)
            }
        };
        let mut max_fraction = 1.0f32;
        let rest = self.untreed_after_tree(|tree| {
            let moved = &self.shapes.moved_flags;
            tree.ray_cast(
                &self.shapes.swept_boxes,
                origin,
                translation,
                max_fraction,
                |s, max| {
                    if moved[s as usize] {
                        return max;
                    }
                    max_fraction = visit(s, max);
                    max_fraction
                },
            );
        });
        for s in rest {
            if max_fraction <= 0.0 {
                return;
            }
            if ray_may_cross(
                &self.shapes.swept_boxes[s as usize],
                origin,
                translation,
                max_fraction,
            ) {
                max_fraction = visit(s, max_fraction);
            }
        }
    }

    /// The nearest hit of the ray `origin + t · translation`, t in [0, 1], among the shapes
    /// `filter` sees (Box2D's `b2World_CastRayClosest`).
    pub fn cast_ray_closest(
        &self,
        origin: Vec2,
        translation: Vec2,
        filter: &QueryFilter,
    ) -> Option<RayHit> {
        let mut best: Option<RayHit> = None;
        self.cast_ray(origin, translation, filter, |hit| {
            // Of two hits at the same fraction, the lower shape slot, whatever the tree's order.
            if best.is_none_or(|b| {
                (hit.fraction, hit.shape.shape.index) < (b.fraction, b.shape.shape.index)
            }) {
                best = Some(*hit);
            }
            hit.fraction
        });
        best
    }

    /// Every hit of the ray `origin + t · translation`, t in [0, 1], among the shapes `filter`
    /// sees, nearest first (ties by shape slot).
    pub fn cast_ray_all(
        &self,
        origin: Vec2,
        translation: Vec2,
        filter: &QueryFilter,
    ) -> Vec<RayHit> {
        let mut hits = Vec::new();
        self.cast_ray(origin, translation, filter, |hit| {
            hits.push(*hit);
            1.0
        });
        hits.sort_by(|a, b| {
            (a.fraction, a.shape.shape.index)
                .partial_cmp(&(b.fraction, b.shape.shape.index))
                .expect("fractions are finite")
        });
        hits
    }

    /// Moves `shape` from `pose` along `translation` (without turning) and calls `f` with each
    /// shape `filter` sees that it would meet, where it meets it first (Box2D's
    /// `b2World_CastShape`): the hit's `fraction` of the translation, the `point` on the
    /// other shape's surface and its outward `normal` there. `f` returns as for
    /// [`World::cast_ray`] (the fraction to clip to, 1 to go on, 0 to stop, negative to ignore
    /// the shape). Time of impact as continuous collision finds it (conservative advancement
    /// to Box2D's target: rounded surfaces a linear slop into each other, sharp cores a slop
    /// apart); a shape already overlapping one is a hit at fraction 0 with the normal against
    /// the motion. Hits come in shape-slot order.
    pub fn cast_shape(
        &self,
        shape: &Shape,
        pose: Transform,
        translation: Vec2,
        filter: &QueryFilter,
        mut f: impl FnMut(&RayHit) -> f32,
    ) {
        let finite = pose.p.is_finite()
            && pose.q.c.is_finite()
            && pose.q.s.is_finite()
            && translation.is_finite();
        if !finite {
            return;
        }
        let end = Transform {
            p: pose.p + translation,
            q: pose.q,
        };
        let swept = shape.aabb(pose).union(&shape.aabb(end));
        let candidates = self.shapes_in_box_sorted(&swept, filter);
        let proxy = Proxy::of(shape, Transform::IDENTITY);
        let sweep = Sweep {
            c0: pose.p,
            c1: end.p,
            q0: pose.q,
            q1: pose.q,
        };
        let mut max_fraction = 1.0f32;
        for s in candidates {
            let other = Proxy::of(&self.shapes.geometry[s as usize], Transform::IDENTITY);
            let other_pose = self.shape_pose(s);
            let hit = match time_of_impact(
                &other,
                &Sweep::still(other_pose),
                &proxy,
                &sweep,
                max_fraction,
            ) {
                Impact::Apart => continue,
                Impact::Overlapping => RayHit {
                    shape: self.shape_ref(s),
                    point: pose.p,
                    normal: -translation.normalize_or_zero(),
                    fraction: 0.0,
                },
                Impact::At(t) => {
                    let c = distance(&other, other_pose, &proxy, sweep.at(t));
                    let normal = (c.point_b - c.point_a).normalize_or_zero();
                    RayHit {
                        shape: self.shape_ref(s),
                        point: c.point_a + normal * other.radius,
                        normal,
                        fraction: t,
                    }
                }
            };
            let value = f(&hit);
            if value == 0.0 {
                return;
            }
            if value > 0.0 {
                max_fraction = max_fraction.min(value);
            }
        }
    }

    /// The first shape `shape`, moved from `pose` along `translation`, would meet, of those
    /// `filter` sees (see [`World::cast_shape`]; of two met at once, the lower slot).
    pub fn cast_shape_closest(
        &self,
        shape: &Shape,
        pose: Transform,
        translation: Vec2,
        filter: &QueryFilter,
    ) -> Option<RayHit> {
        let mut best: Option<RayHit> = None;
        self.cast_shape(shape, pose, translation, filter, |hit| {
            if best.is_none_or(|b| hit.fraction < b.fraction) {
                best = Some(*hit);
            }
            hit.fraction.max(f32::MIN_POSITIVE)
        });
        best
    }

    /// Calls `f` with every shape `filter` sees whose bounding box overlaps `aabb`, until it
    /// returns false (Box2D's `b2World_OverlapAABB`, tested against each shape's tight box
    /// rather than its fat one).
    pub fn overlap_aabb(
        &self,
        aabb: &Aabb,
        filter: &QueryFilter,
        mut f: impl FnMut(ShapeRef) -> bool,
    ) {
        self.shapes_in_box(aabb, filter, |s| {
            let tight = self.shapes.geometry[s as usize].aabb(self.shape_pose(s));
            !tight.overlaps(aabb) || f(self.shape_ref(s))
        });
    }

    /// Calls `f` with every shape `filter` sees that contains `point`, until it returns false
    /// (segments and chains contain nothing).
    pub fn overlap_point(
        &self,
        point: Vec2,
        filter: &QueryFilter,
        mut f: impl FnMut(ShapeRef) -> bool,
    ) {
        let at = Aabb {
            min: point,
            max: point,
        };
        self.shapes_in_box(&at, filter, |s| {
            let local = self.shape_pose(s).apply_inv(point);
            !self.shapes.geometry[s as usize].contains(local) || f(self.shape_ref(s))
        });
    }

    /// Calls `f` with every shape `filter` sees that overlaps `shape` placed at `pose`, until
    /// it returns false (Box2D's `b2World_OverlapShape`). Two shapes without area (segments,
    /// chain segments) overlap where they cross or touch.
    pub fn overlap_shape(
        &self,
        shape: &Shape,
        pose: Transform,
        filter: &QueryFilter,
        mut f: impl FnMut(ShapeRef) -> bool,
    ) {
        let aabb = shape.aabb(pose);
        self.shapes_in_box(&aabb, filter, |s| {
            !shapes_overlap(
                shape,
                pose,
                &self.shapes.geometry[s as usize],
                self.shape_pose(s),
            ) || f(self.shape_ref(s))
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::def::{BodyDef, BodyKind, PartDef, ShapeDef};
    use crate::id::BodyId;
    use crate::world::StepSettings;

    fn unit_box() -> ShapeDef {
        ShapeDef::Box {
            half_extents: [0.5, 0.5],
            radius: 0.0,
        }
    }

    /// Five static unit boxes centred at x = 0, 2, ..., 8 on y = 0; the third in category 2.
    fn row() -> (World, Vec<BodyId>) {
        let mut w = World::new(StepSettings::default());
        let ids = (0..5)
            .map(|i| {
                let mut def = BodyDef::new(unit_box())
                    .kind(BodyKind::Static)
                    .at(2.0 * i as f32, 0.0);
                if i == 2 {
                    def = def.filter(Filter {
                        category: 2,
                        ..Filter::default()
                    });
                }
                w.create_body(&def).unwrap()
            })
            .collect();
        (w, ids)
    }

    #[test]
    fn a_ray_along_a_row_meets_its_boxes_in_order_and_obeys_its_filter() {
        let (mut w, ids) = row();
        // Run before the tree exists, and after a step has built it.
        for stepped in [false, true] {
            if stepped {
                w.step(1.0 / 60.0, 4);
            }
            let (o, d) = (Vec2::new(-2.0, 0.25), Vec2::new(12.0, 0.0));
            let all = w.cast_ray_all(o, d, &QueryFilter::default());
            let bodies: Vec<BodyId> = all.iter().map(|h| h.shape.body).collect();
            assert_eq!(bodies, ids, "stepped {stepped}");
            // The first box's left face at x = -0.5: 1.5 of 12.
            let first = w.cast_ray_closest(o, d, &QueryFilter::default()).unwrap();
            assert!((first.fraction - 1.5 / 12.0).abs() < 1e-6, "{first:?}");
            assert!((first.point - Vec2::new(-0.5, 0.25)).length() < 1e-5);
            assert_eq!(first.normal, Vec2::new(-1.0, 0.0));
            // A query that does not see category 2 passes the third box.
            let not_two = QueryFilter {
                mask: !2,
                ..QueryFilter::default()
            };
            let seen: Vec<BodyId> = w
                .cast_ray_all(o, d, &not_two)
                .iter()
                .map(|h| h.shape.body)
                .collect();
            assert_eq!(seen, [ids[0], ids[1], ids[3], ids[4]]);
            // A query that leaves out the first body: the closest hit is the second, and
            // no cast, overlap or shape cast sees the first.
            let not_first = QueryFilter::default().excluding(ids[0]);
            let next = w.cast_ray_closest(o, d, &not_first).unwrap();
            assert_eq!(next.shape.body, ids[1]);
            let first_box = w.body(ids[0]).unwrap().position;
            let mut seen = Vec::new();
            w.overlap_point(first_box, &not_first, |r| {
                seen.push(r.body);
                true
            });
            assert!(seen.is_empty(), "{seen:?}");
            w.overlap_point(first_box, &QueryFilter::default(), |r| {
                seen.push(r.body);
                true
            });
            assert_eq!(seen, [ids[0]]);
            // Ignoring every hit (a negative return) and stopping at the first (0).
            let mut calls = 0;
            w.cast_ray(o, d, &QueryFilter::default(), |_| {
                calls += 1;
                -1.0
            });
            assert_eq!(calls, 5);
            let mut calls = 0;
            w.cast_ray(o, d, &QueryFilter::default(), |_| {
                calls += 1;
                0.0
            });
            assert_eq!(calls, 1);
        }
    }

    /// A scatter of every shape with area on dynamic bodies, some with a sensor part, over a
    /// static floor segment.
    fn scatter() -> World {
        let mut w = World::new(StepSettings::default());
        w.create_body(
            &BodyDef::new(ShapeDef::Segment {
                point1: [-30.0, 0.0],
                point2: [30.0, 0.0],
            })
            .kind(BodyKind::Static),
        )
        .unwrap();
        let mut seed = 7u32;
        let mut next = move || {
            seed = seed.wrapping_mul(1664525).wrapping_add(1013904223);
            (seed >> 8) as f32 / (1u32 << 24) as f32
        };
        for i in 0..120 {
            let shape = match i % 4 {
                0 => ShapeDef::Circle {
                    radius: 0.2 + next(),
                },
                1 => unit_box(),
                2 => ShapeDef::Capsule {
                    center1: [-0.5, 0.0],
                    center2: [0.5, 0.0],
                    radius: 0.3,
                },
                _ => ShapeDef::Box {
                    half_extents: [0.6, 0.3],
                    radius: 0.2,
                },
            };
            let mut parts = vec![PartDef::new(shape)];
            if i % 10 == 0 {
                parts.push(PartDef::new(ShapeDef::Circle { radius: 1.5 }).sensor(true));
            }
            let def = BodyDef::compound(parts)
                .at(-25.0 + 50.0 * next(), 1.0 + 20.0 * next())
                .angle(6.0 * next());
            w.create_body(&def).unwrap();
        }
        w
    }

    /// Every hit, by brute force: each live shape the filter sees, cast against directly.
    fn brute_hits(w: &World, o: Vec2, d: Vec2, filter: &QueryFilter) -> Vec<(u32, u32)> {
        let mut hits: Vec<(u32, u32)> = w
            .shapes()
            .filter(|v| filter.sensors || !v.sensor)
            .filter_map(|v| {
                let local = Ray {
                    origin: v.transform.apply_inv(o),
                    translation: v.transform.q.apply_inv(d),
                    max_fraction: 1.0,
                };
                ray_cast(v.shape, &local).map(|h| (h.fraction.to_bits(), v.id.index))
            })
            .collect();
        hits.sort();
        hits
    }

    #[test]
    fn ray_casts_and_overlaps_find_what_a_scan_of_every_shape_finds() {
        let mut w = scatter();
        // Fresh (no tree), mid-fall (a stale tree and a moved list), after a shape is added
        // between steps (every shape tested until the next step).
        for phase in 0..3 {
            match phase {
                1 => (0..40).for_each(|_| w.step(1.0 / 60.0, 4)),
                2 => {
                    w.create_body(&BodyDef::new(unit_box()).at(0.0, 5.0))
                        .unwrap();
                }
                _ => {}
            }
            for k in 0..40 {
                let a = 0.1 + k as f32 * 0.15;
                let o = Vec2::new(-28.0 + 1.4 * k as f32, 22.0);
                let d = Vec2::new(a.cos(), -a.sin().abs()) * 60.0;
                for filter in [QueryFilter::default(), QueryFilter::ALL] {
                    let found: Vec<(u32, u32)> = w
                        .cast_ray_all(o, d, &filter)
                        .iter()
                        .map(|h| (h.fraction.to_bits(), h.shape.shape.index))
                        .collect();
                    let mut sorted = found.clone();
                    sorted.sort();
                    assert_eq!(found, sorted, "nearest first");
                    assert_eq!(
                        found,
                        brute_hits(&w, o, d, &filter),
                        "phase {phase} ray {k}"
                    );
                    let closest = w.cast_ray_closest(o, d, &filter);
                    assert_eq!(
                        closest.map(|h| (h.fraction.to_bits(), h.shape.shape.index)),
                        found.first().copied()
                    );
                }
                // Point, box and shape overlaps against the same scan.
                let p = o + d * 0.3;
                let mut at: Vec<u32> = Vec::new();
                w.overlap_point(p, &QueryFilter::ALL, |r| {
                    at.push(r.shape.index);
                    true
                });
                at.sort();
                let brute: Vec<u32> = w
                    .shapes()
                    .filter(|v| v.shape.contains(v.transform.apply_inv(p)))
                    .map(|v| v.id.index)
                    .collect();
                assert_eq!(at, brute, "phase {phase} point {k}");
                let region = Aabb {
                    min: p - Vec2::splat(2.0),
                    max: p + Vec2::splat(2.0),
                };
                let mut inside: Vec<u32> = Vec::new();
                w.overlap_aabb(&region, &QueryFilter::default(), |r| {
                    inside.push(r.shape.index);
                    true
                });
                inside.sort();
                let brute: Vec<u32> = w
                    .shapes()
                    .filter(|v| !v.sensor && v.shape.aabb(v.transform).overlaps(&region))
                    .map(|v| v.id.index)
                    .collect();
                assert_eq!(inside, brute, "phase {phase} box {k}");
                let probe = Shape::Circle(crate::shape::Circle { radius: 2.0 });
                let pose = Transform {
                    p,
                    q: crate::math::Rot::IDENTITY,
                };
                let mut touching: Vec<u32> = Vec::new();
                w.overlap_shape(&probe, pose, &QueryFilter::default(), |r| {
                    touching.push(r.shape.index);
                    true
                });
                touching.sort();
                let brute: Vec<u32> = w
                    .shapes()
                    .filter(|v| !v.sensor && shapes_overlap(&probe, pose, v.shape, v.transform))
                    .map(|v| v.id.index)
                    .collect();
                assert_eq!(touching, brute, "phase {phase} shape {k}");
            }
        }
        // body_at is a point query too: the body of the last shape (in slot order) there.
        for v in w.shapes().filter(|v| v.shape.has_area()) {
            let p = v.transform.p;
            let top = w
                .shapes()
                .filter(|u| u.shape.contains(u.transform.apply_inv(p)))
                .last()
                .map(|u| u.body);
            assert_eq!(w.body_at(p), top);
        }
    }

    #[test]
    fn segments_overlap_where_they_cross_or_touch() {
        // Two shapes without area (Box2D's rule: distance within 10 f32::EPSILON).
        let seg = |x1: f32, y1: f32, x2: f32, y2: f32| {
            Shape::Segment(crate::shape::Segment {
                point1: Vec2::new(x1, y1),
                point2: Vec2::new(x2, y2),
            })
        };
        let at = |x: f32, y: f32| Transform {
            p: Vec2::new(x, y),
            q: crate::math::Rot::IDENTITY,
        };
        let cross = seg(-1.0, 0.0, 1.0, 0.0);
        let post = seg(0.0, -0.5, 0.0, 0.5);
        assert!(shapes_overlap(&cross, at(0.0, 0.0), &post, at(0.0, 0.0)));
        // Touching at an end: the post's top on the crossbar.
        assert!(shapes_overlap(&cross, at(0.0, 0.5), &post, at(0.0, 0.0)));
        // A millimetre above the post, and parallel a millimetre apart: apart.
        assert!(!shapes_overlap(&cross, at(0.0, 0.501), &post, at(0.0, 0.0)));
        assert!(!shapes_overlap(
            &cross,
            at(0.0, 0.001),
            &cross,
            at(0.0, 0.0)
        ));
        // Through the world's query as well.
        let mut w = World::new(StepSettings::default());
        w.create_body(
            &BodyDef::new(ShapeDef::Segment {
                point1: [0.0, -0.5],
                point2: [0.0, 0.5],
            })
            .kind(BodyKind::Static),
        )
        .unwrap();
        let mut found = 0;
        w.overlap_shape(&cross, at(0.0, 0.2), &QueryFilter::default(), |_| {
            found += 1;
            true
        });
        assert_eq!(found, 1);
        found = 0;
        w.overlap_shape(&cross, at(0.0, 0.7), &QueryFilter::default(), |_| {
            found += 1;
            true
        });
        assert_eq!(found, 0);
    }

    #[test]
    fn a_disc_cast_down_meets_the_ground_where_the_closed_form_says() {
        let mut w = World::new(StepSettings::default());
        let ground = w
            .create_body(
                &BodyDef::new(ShapeDef::Box {
                    half_extents: [10.0, 0.5],
                    radius: 0.0,
                })
                .kind(BodyKind::Static)
                .at(0.0, -0.5),
            )
            .unwrap();
        let disc = Shape::Circle(crate::shape::Circle { radius: 0.5 });
        let from = Transform {
            p: Vec2::new(1.0, 5.0),
            q: crate::math::Rot::IDENTITY,
        };
        let hit = w
            .cast_shape_closest(&disc, from, Vec2::new(0.0, -10.0), &QueryFilter::default())
            .expect("it meets the ground");
        // Its surface reaches y = 0 after 4.5 m of 10; the time of impact stops with the two
        // surfaces a linear slop into each other (Box2D's target for rounded shapes), give or
        // take a quarter slop.
        let expected = (4.5 + crate::LINEAR_SLOP) / 10.0;
        assert!(
            (hit.fraction - expected).abs() <= 0.25 * crate::LINEAR_SLOP / 10.0 + 1e-6,
            "{hit:?}"
        );
        assert_eq!(hit.shape.body, ground);
        assert!((hit.normal - Vec2::Y).length() < 1e-5, "{hit:?}");
        assert!((hit.point - Vec2::new(1.0, 0.0)).length() < 1e-4, "{hit:?}");
        // Sideways above the ground it meets nothing; started in the ground, it is a hit at 0.
        let above =
            w.cast_shape_closest(&disc, from, Vec2::new(10.0, 0.0), &QueryFilter::default());
        assert!(above.is_none());
        let inside = Transform {
            p: Vec2::new(0.0, 0.0),
            q: crate::math::Rot::IDENTITY,
        };
        let hit = w
            .cast_shape_closest(&disc, inside, Vec2::new(1.0, 0.0), &QueryFilter::default())
            .unwrap();
        assert_eq!(hit.fraction, 0.0);
    }

    #[test]
    fn shape_casts_find_what_a_sweep_against_every_shape_finds() {
        let mut w = scatter();
        (0..40).for_each(|_| w.step(1.0 / 60.0, 4));
        let probe = Shape::Capsule(crate::shape::Capsule {
            center1: Vec2::new(-0.4, 0.0),
            center2: Vec2::new(0.4, 0.0),
            radius: 0.2,
        });
        let mut hits = 0;
        for k in 0..30 {
            let pose = Transform {
                p: Vec2::new(-28.0 + 1.9 * k as f32, 24.0),
                q: crate::math::Rot::from_angle(0.3 * k as f32),
            };
            let d = Vec2::new((0.2 * k as f32).cos() * 10.0, -30.0);
            let found = w
                .cast_shape_closest(&probe, pose, d, &QueryFilter::default())
                .map(|h| (h.fraction.to_bits(), h.shape.shape.index));
            let sweep = Sweep {
                c0: pose.p,
                c1: pose.p + d,
                q0: pose.q,
                q1: pose.q,
            };
            let proxy = Proxy::of(&probe, Transform::IDENTITY);
            let brute = w
                .shapes()
                .filter(|v| !v.sensor)
                .filter_map(|v| {
                    let other = Proxy::of(v.shape, Transform::IDENTITY);
                    match time_of_impact(&other, &Sweep::still(v.transform), &proxy, &sweep, 1.0) {
                        Impact::At(t) => Some((t.to_bits(), v.id.index)),
                        Impact::Overlapping => Some((0, v.id.index)),
                        Impact::Apart => None,
                    }
                })
                .min();
            assert_eq!(found, brute, "cast {k}");
            hits += usize::from(found.is_some());
        }
        assert!(hits > 20, "{hits} of 30 casts met something");
    }

    #[test]
    fn a_ray_that_passes_nothing_hits_nothing_and_bad_input_is_no_hit() {
        let w = scatter();
        assert!(
            w.cast_ray_closest(
                Vec2::new(-40.0, 50.0),
                Vec2::new(80.0, 0.0),
                &QueryFilter::default()
            )
            .is_none()
        );
        assert!(
            w.cast_ray_closest(Vec2::new(f32::NAN, 0.0), Vec2::X, &QueryFilter::default())
                .is_none()
        );
    }
}
