//! The world's side of the character mover ([`crate::mover`]): a capsule cast through the
//! broad phase, and the planes of the shapes it overlaps (Box2D v3.1's `b2World_CastMover`
//! and `b2World_CollideMover`).

use glam::Vec2;

use super::World;
use crate::collision::distance::{Proxy, distance};
use crate::math::Transform;
use crate::mover::{Plane, PlaneResult};
use crate::shape::{Aabb, Capsule, Shape};
use crate::world::QueryFilter;

/// Whether a capsule can be a mover: finite, with a radius above 0 (Box2D asserts more than
/// two linear slops; a thinner one still works here, it only snags sooner).
fn usable(mover: &Capsule) -> bool {
    mover.center1.is_finite()
        && mover.center2.is_finite()
        && mover.radius.is_finite()
        && mover.radius > 0.0
}

/// The mover's queries.
///
/// ```
/// use tumble_physics::mover::{CollisionPlane, clip_vector, solve_planes};
/// use tumble_physics::{BodyDef, BodyKind, Capsule, QueryFilter, ShapeDef, StepSettings, Vec2, World};
///
/// let mut world = World::new(StepSettings::default());
/// world
///     .create_body(&BodyDef::new(ShapeDef::Box { half_extents: [10.0, 0.5], radius: 0.0 }).kind(BodyKind::Static).at(0.0, -0.5))
///     .unwrap();
/// // A capsule 0.3 m in radius standing 2 cm deep in the ground, wanting to walk and fall.
/// let mover = Capsule { center1: Vec2::new(0.0, 0.28), center2: Vec2::new(0.0, 1.0), radius: 0.3 };
/// let filter = QueryFilter::default();
/// let mut planes: Vec<CollisionPlane> = world
///     .collide_mover(&mover, &filter)
///     .iter()
///     .map(|r| CollisionPlane::new(r.plane))
///     .collect();
/// let step = solve_planes(Vec2::new(0.1, -0.2), &mut planes);
/// // It walks on, lifted to a linear slop inside the ground.
/// assert!((step.translation - Vec2::new(0.1, 0.015)).length() < 1e-4);
/// let velocity = clip_vector(Vec2::new(6.0, -12.0), &planes);
/// assert!((velocity - Vec2::new(6.0, 0.0)).length() < 1e-4);
/// // Cast down from 1 m up, it stops at the ground, about half way down 2 m.
/// let high = Capsule { center1: Vec2::new(0.0, 1.3), ..mover };
/// let high = Capsule { center2: Vec2::new(0.0, 2.0), ..high };
/// let fraction = world.cast_mover(&high, Vec2::new(0.0, -2.0), &filter);
/// assert!((fraction - 0.5).abs() < 0.01, "{fraction}");
/// ```
impl World {
    /// How far along `translation` (0 to 1) the capsule `mover`, given in world coordinates,
    /// moves before it touches a shape that `filter` sees and that is not a sensor (Box2D's
    /// `b2World_CastMover`). A shape it overlaps at the start is ignored, so a mover resting
    /// a slop inside the ground can walk off; 1 when it touches nothing, and for a capsule
    /// that is not one (a radius not above 0, a number not finite).
    pub fn cast_mover(&self, mover: &Capsule, translation: Vec2, filter: &QueryFilter) -> f32 {
        if !usable(mover) {
            return 1.0;
        }
        let filter = QueryFilter {
            sensors: false,
            ..*filter
        };
        let mut fraction = 1.0f32;
        self.cast_shape(
            &Shape::Capsule(*mover),
            Transform::IDENTITY,
            translation,
            &filter,
            |hit| {
                if hit.fraction == 0.0 {
                    // Overlapping at the start: ignored.
                    return -1.0;
                }
                fraction = fraction.min(hit.fraction);
                fraction
            },
        );
        fraction
    }

    /// The planes that push on the capsule `mover` (world coordinates): one for each shape
    /// that `filter` sees, not a sensor, within the capsule's radius of its segment, in shape
    /// slot order (Box2D's `b2World_CollideMover`). Each plane's normal points from the
    /// shape to the mover and its offset is how deep the mover is; a shape whose core the
    /// mover's segment crosses gives no normal and is left out, as Box2D does. Chains and
    /// segments push from both sides. None for a capsule that is not one (as
    /// [`World::cast_mover`]).
    pub fn collide_mover(&self, mover: &Capsule, filter: &QueryFilter) -> Vec<PlaneResult> {
        let filter = QueryFilter {
            sensors: false,
            ..*filter
        };
        if !usable(mover) {
            return Vec::new();
        }
        let r = Vec2::splat(mover.radius);
        let aabb = Aabb {
            min: mover.center1.min(mover.center2) - r,
            max: mover.center1.max(mover.center2) + r,
        };
        let candidates = self.shapes_in_box_sorted(&aabb, &filter);
        let core = Proxy::points(&[mover.center1, mover.center2], 0.0, Transform::IDENTITY);
        let mut planes = Vec::new();
        for s in candidates {
            let shape = Proxy::of(&self.shapes.geometry[s as usize], Transform::IDENTITY);
            let c = distance(&shape, self.shape_pose(s), &core, Transform::IDENTITY);
            let total = mover.radius + shape.radius;
            if c.distance > total {
                continue;
            }
            let normal = (c.point_b - c.point_a).normalize_or_zero();
            if normal == Vec2::ZERO {
                continue;
            }
            planes.push(PlaneResult {
                plane: Plane {
                    normal,
                    offset: total - c.distance,
                },
                point: c.point_a + normal * shape.radius,
                hit: true,
                shape: self.shape_ref(s),
            });
        }
        planes
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec2;

    use super::*;
    use crate::def::{BodyDef, BodyKind, PartDef, ShapeDef};
    use crate::mover::{CollisionPlane, clip_vector, solve_planes};
    use crate::world::StepSettings;

    const RADIUS: f32 = 0.3;

    /// A static ground with its top along y = 0 from x = −10 to 10.
    fn ground() -> World {
        let mut w = World::new(StepSettings::default());
        w.create_body(
            &BodyDef::new(ShapeDef::Box {
                half_extents: [10.0, 0.5],
                radius: 0.0,
            })
            .kind(BodyKind::Static)
            .at(0.0, -0.5),
        )
        .unwrap();
        w
    }

    /// The mover standing with its feet at `p`: segment from 0.3 to 1.0 m above it.
    fn capsule_at(p: Vec2) -> Capsule {
        Capsule {
            center1: p + Vec2::new(0.0, RADIUS),
            center2: p + Vec2::new(0.0, 1.0),
            radius: RADIUS,
        }
    }

    #[test]
    fn the_ground_gives_one_plane_as_deep_as_the_mover_stands_in_it() {
        let w = ground();
        let planes = w.collide_mover(&capsule_at(Vec2::new(1.0, -0.02)), &QueryFilter::default());
        assert_eq!(planes.len(), 1);
        let p = planes[0];
        // Exact to f32 roundings of numbers of order 1 (1e-5).
        assert!((p.plane.normal - Vec2::Y).length() < 1e-5, "{p:?}");
        assert!((p.plane.offset - 0.02).abs() < 1e-5);
        assert!((p.point - Vec2::new(1.0, 0.0)).length() < 1e-5);
        // Above the ground, or with the ground's body left out: nothing.
        assert!(
            w.collide_mover(&capsule_at(Vec2::new(1.0, 0.1)), &QueryFilter::default())
                .is_empty()
        );
        let ground_body = p.shape.body;
        let without = QueryFilter::default().excluding(ground_body);
        assert!(
            w.collide_mover(&capsule_at(Vec2::new(1.0, -0.02)), &without)
                .is_empty()
        );
    }

    #[test]
    fn sensors_are_not_planes_and_a_chain_pushes_from_both_sides() {
        let mut w = World::new(StepSettings::default());
        w.create_body(
            &BodyDef::compound(vec![
                PartDef::new(ShapeDef::Box {
                    half_extents: [1.0, 1.0],
                    radius: 0.0,
                })
                .sensor(true),
            ])
            .kind(BodyKind::Static),
        )
        .unwrap();
        let at = capsule_at(Vec2::new(0.0, -0.5));
        assert!(w.collide_mover(&at, &QueryFilter::ALL).is_empty());
        assert_eq!(
            w.cast_mover(&at, Vec2::new(0.0, 1.0), &QueryFilter::ALL),
            1.0
        );
        // A chain along y = 3, running left to right (it pushes downwards in the solver):
        // the mover's head just under it gets a plane pushing it down, its feet just over it
        // one pushing it up.
        w.create_body(
            &BodyDef::new(ShapeDef::Chain {
                points: vec![[-6.0, 3.0], [-4.0, 3.0], [4.0, 3.0], [6.0, 3.0]],
                looped: false,
            })
            .kind(BodyKind::Static),
        )
        .unwrap();
        let below = w.collide_mover(&capsule_at(Vec2::new(0.0, 1.71)), &QueryFilter::default());
        assert_eq!(below.len(), 1);
        assert!(
            (below[0].plane.normal + Vec2::Y).length() < 1e-5,
            "{below:?}"
        );
        let above = w.collide_mover(&capsule_at(Vec2::new(0.0, 2.99)), &QueryFilter::default());
        assert_eq!(above.len(), 1);
        assert!(
            (above[0].plane.normal - Vec2::Y).length() < 1e-5,
            "{above:?}"
        );
    }

    #[test]
    fn a_cast_stops_at_the_ground_and_ignores_what_it_starts_inside() {
        let w = ground();
        // Feet 1 m up, cast 2 m down: it stops after 1 m, the rounded surfaces a linear slop
        // into each other (the cast's target, as continuous collision's), fraction
        // (1 + 0.005) / 2, within the target's own tolerance (a quarter slop, 0.0006 of 2 m).
        let f = w.cast_mover(
            &capsule_at(Vec2::new(0.0, 1.0)),
            Vec2::new(0.0, -2.0),
            &QueryFilter::default(),
        );
        assert!((f - 0.5025).abs() < 0.001, "{f}");
        // Standing a slop inside the ground, it walks off unhindered.
        let f = w.cast_mover(
            &capsule_at(Vec2::new(0.0, -0.004)),
            Vec2::new(3.0, 0.0),
            &QueryFilter::default(),
        );
        assert_eq!(f, 1.0);
        // A bad number is no hit, not a panic.
        let nan = capsule_at(Vec2::new(f32::NAN, 0.0));
        let flat = Capsule {
            radius: -0.1,
            ..capsule_at(Vec2::new(0.0, -0.05))
        };
        for bad in [nan, flat] {
            assert_eq!(w.cast_mover(&bad, Vec2::X, &QueryFilter::default()), 1.0);
            assert!(w.collide_mover(&bad, &QueryFilter::default()).is_empty());
        }
    }

    /// One frame of the mover as Box2D's character sample moves it: up to five rounds of
    /// collide, solve the planes toward the target, cast the solved translation; then the
    /// velocity clipped by the planes that pushed. Returns the new feet position and velocity.
    fn move_frame(w: &World, feet: Vec2, velocity: Vec2, dt: f32) -> (Vec2, Vec2) {
        let filter = QueryFilter::default();
        let target = feet + velocity * dt;
        let mut feet = feet;
        let mut planes: Vec<CollisionPlane> = Vec::new();
        for _ in 0..5 {
            planes = w
                .collide_mover(&capsule_at(feet), &filter)
                .iter()
                .map(|r| CollisionPlane::new(r.plane))
                .collect();
            let solved = solve_planes(target - feet, &mut planes);
            let fraction = w.cast_mover(&capsule_at(feet), solved.translation, &filter);
            let delta = solved.translation * fraction;
            feet += delta;
            if delta.length() < 0.1 * crate::LINEAR_SLOP {
                break;
            }
        }
        (feet, clip_vector(velocity, &planes))
    }

    #[test]
    fn walking_into_a_wall_stops_at_it_and_never_sinks_into_the_ground() {
        let mut w = ground();
        // A wall whose left face is at x = 3.
        w.create_body(
            &BodyDef::new(ShapeDef::Box {
                half_extents: [0.5, 1.5],
                radius: 0.0,
            })
            .kind(BodyKind::Static)
            .at(3.5, 1.5),
        )
        .unwrap();
        let dt = 1.0 / 60.0;
        let (mut feet, mut v) = (Vec2::new(0.0, 0.0), Vec2::ZERO);
        let mut lowest = 0.0f32;
        for _ in 0..180 {
            // Walk right at 2 m/s, falling under gravity.
            v = Vec2::new(2.0, v.y - 10.0 * dt);
            (feet, v) = move_frame(&w, feet, v, dt);
            lowest = lowest.min(feet.y);
        }
        // Against the wall: its side a slop inside it at most (3 − 0.3 + 0.005), not short
        // of it by more than a slop either; the walk into it clipped away.
        assert!(
            (feet.x - (3.0 - RADIUS)).abs() <= crate::LINEAR_SLOP + 1e-4,
            "{feet}"
        );
        assert!(v.x.abs() < 1e-4, "{v}");
        // The feet never a centimetre into the ground (the issue's bound), and resting a slop
        // inside it (the solver's rule).
        assert!(lowest > -0.01, "{lowest}");
        assert!(feet.y.abs() <= crate::LINEAR_SLOP + 1e-4, "{feet}");
    }

    #[test]
    fn walking_at_a_ramp_climbs_it() {
        let mut w = ground();
        // A 30° ramp from x = 1 rising to the right, 2.31 m high at x = 5.
        let rise = 4.0 * (30f32).to_radians().tan();
        // A body of one polygon is placed by its centroid.
        let centroid = [(1.0 + 5.0 + 5.0) / 3.0, rise / 3.0];
        w.create_body(
            &BodyDef::new(ShapeDef::Polygon {
                vertices: vec![[1.0, 0.0], [5.0, 0.0], [5.0, rise]],
                radius: 0.0,
            })
            .kind(BodyKind::Static)
            .at(centroid[0], centroid[1]),
        )
        .unwrap();
        let dt = 1.0 / 60.0;
        let (mut feet, mut v) = (Vec2::new(-1.0, 0.0), Vec2::ZERO);
        for _ in 0..120 {
            v = Vec2::new(2.0, v.y - 10.0 * dt);
            (feet, v) = move_frame(&w, feet, v, dt);
            // Never inside the ramp by more than a centimetre: its surface under the feet's
            // centre line is at (x − 1)·tan 30°, and the capsule's bottom touches it a
            // radius·(1/cos 30° − 1) above that.
            let surface = ((feet.x - 1.0) * (30f32).to_radians().tan()).max(0.0);
            assert!(feet.y > surface - 0.01, "{feet} under {surface}");
        }
        // Two seconds at up to 2 m/s: well up the ramp.
        assert!(feet.x > 2.5 && feet.y > 0.8, "{feet}");
    }

    #[test]
    fn walking_at_a_low_step_rides_up_over_it() {
        let mut w = ground();
        // A step 5 cm high from x = 2 on: lower than the capsule's 30 cm radius, so its
        // corner's plane leans back towards the mover and lifts it.
        w.create_body(
            &BodyDef::new(ShapeDef::Box {
                half_extents: [4.0, 0.025],
                radius: 0.0,
            })
            .kind(BodyKind::Static)
            .at(6.0, 0.025),
        )
        .unwrap();
        let dt = 1.0 / 60.0;
        let (mut feet, mut v) = (Vec2::new(0.0, 0.0), Vec2::ZERO);
        for _ in 0..120 {
            v = Vec2::new(2.0, v.y - 10.0 * dt);
            (feet, v) = move_frame(&w, feet, v, dt);
        }
        // On top of it, a slop inside its top face (0.05), and on its way.
        assert!(feet.x > 3.0, "{feet}");
        assert!((feet.y - 0.05).abs() <= crate::LINEAR_SLOP + 1e-4, "{feet}");
    }

    #[test]
    fn a_mover_standing_on_a_moving_platform_rides_it_by_the_plane_s_body() {
        let mut w = ground();
        // A kinematic platform 1 m up, moving right at 1.5 m/s.
        let platform = w
            .create_body(
                &BodyDef::new(ShapeDef::Box {
                    half_extents: [1.5, 0.1],
                    radius: 0.0,
                })
                .kind(BodyKind::Kinematic)
                .at(0.0, 0.9)
                .velocity(1.5, 0.0),
            )
            .unwrap();
        let dt = 1.0 / 60.0;
        let mut feet = Vec2::new(0.0, 1.0);
        let mut v = Vec2::ZERO;
        for _ in 0..60 {
            // The game's rule, as Box2D's sample has it: standing on a body, the mover takes
            // its velocity (here only the platform moves), plus its own fall.
            let filter = QueryFilter::default();
            let under = w
                .collide_mover(&capsule_at(feet - Vec2::new(0.0, 0.01)), &filter)
                .into_iter()
                .find(|r| r.plane.normal.y > 0.7);
            let carried = under
                .and_then(|r| w.body(r.shape.body).ok())
                .map_or(Vec2::ZERO, |b| b.linear_velocity);
            v = Vec2::new(carried.x, v.y - 10.0 * dt);
            (feet, v) = move_frame(&w, feet, v, dt);
            w.step(dt, 4);
            assert_eq!(under.map(|r| r.shape.body), Some(platform));
        }
        // A second on it: carried 1.5 m with it, still standing on its top (y = 1).
        let on = w.body(platform).unwrap().position;
        assert!((feet.x - on.x).abs() < 0.05, "{feet} on {on}");
        assert!((feet.y - 1.0).abs() < 0.01, "{feet}");
    }
}
