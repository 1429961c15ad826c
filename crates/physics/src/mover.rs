//! The character mover, as Box2D v3.1 has it (`mover.c`, `b2World_CastMover`,
//! `b2World_CollideMover`): a capsule moved kinematically by the game, not simulated. Each
//! frame the game casts it along the motion it wants ([`World::cast_mover`]), gathers the
//! planes that push on it where it ends up ([`World::collide_mover`]), solves for the
//! translation that respects them ([`solve_planes`]) and takes the part of its velocity
//! that does not run into them ([`clip_vector`]). The planes' push limits let it climb steps
//! and stand on slopes as the game decides.
//!
//! [`World::cast_mover`]: crate::World::cast_mover
//! [`World::collide_mover`]: crate::World::collide_mover

use glam::Vec2;

use crate::LINEAR_SLOP;
use crate::world::ShapeRef;

/// A plane (a line in 2D): the points `p` with `normal · p = offset`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Plane {
    /// Unit normal.
    pub normal: Vec2,
    /// Signed offset along the normal. For a plane of [`World::collide_mover`] it is how far
    /// the mover is inside the shape along the normal (how far it must move out).
    ///
    /// [`World::collide_mover`]: crate::World::collide_mover
    pub offset: f32,
}

impl Plane {
    /// How far `point` is past the plane along its normal: `normal · point − offset`
    /// (Box2D's `b2PlaneSeparation`).
    pub fn separation(&self, point: Vec2) -> f32 {
        self.normal.dot(point) - self.offset
    }
}

/// A plane that pushes on the mover, from [`World::collide_mover`].
///
/// [`World::collide_mover`]: crate::World::collide_mover
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlaneResult {
    /// Its normal points from the shape to the mover; its offset is how deep the mover is.
    pub plane: Plane,
    /// The closest point on the shape's surface (Box2D gives the point on the shape's core,
    /// which for a circle is its centre).
    pub point: Vec2,
    /// Whether the mover touches the shape (always, for the planes the world gives).
    pub hit: bool,
    /// The shape, and its body (a platform the mover stands on, whose velocity it takes).
    pub shape: ShapeRef,
}

/// A plane as [`solve_planes`] uses it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CollisionPlane {
    /// The plane.
    pub plane: Plane,
    /// The most this plane may push the mover (m): `f32::MAX` for a wall, 0 for a plane
    /// the mover should pass (a step it climbs, a slope too steep to stand on, as the
    /// game decides).
    pub push_limit: f32,
    /// How far it pushed in the last solve (output).
    pub push: f32,
    /// Whether [`clip_vector`] takes the velocity into it away.
    pub clip_velocity: bool,
}

impl CollisionPlane {
    /// A plane of a collision, pushing without limit and clipping the velocity.
    pub fn new(plane: Plane) -> CollisionPlane {
        CollisionPlane {
            plane,
            push_limit: f32::MAX,
            push: 0.0,
            clip_velocity: true,
        }
    }
}

/// What [`solve_planes`] found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlaneSolverResult {
    /// The translation to apply to the mover.
    pub translation: Vec2,
    /// Iterations it took (at most 20).
    pub iteration_count: u32,
}

/// Most iterations of [`solve_planes`] (Box2D's).
const PLANE_ITERATIONS: u32 = 20;

/// The translation nearest `target_delta` that leaves the mover at most a linear slop inside
/// each plane, each plane pushing at most its `push_limit` (Box2D's `b2SolvePlanes`: Gauss-
/// Seidel over the planes, each push accumulated and clamped to `[0, push_limit]`, until
/// the pushes of a sweep sum to under a linear slop or 20 sweeps). Each plane's `push` is set.
pub fn solve_planes(target_delta: Vec2, planes: &mut [CollisionPlane]) -> PlaneSolverResult {
    for p in planes.iter_mut() {
        p.push = 0.0;
    }
    let mut delta = target_delta;
    let mut iteration = 0;
    while iteration < PLANE_ITERATIONS {
        let mut total_push = 0.0f32;
        for p in planes.iter_mut() {
            // The slop keeps it resting a hair inside, so it does not jitter in and out.
            let separation = p.plane.separation(delta) + LINEAR_SLOP;
            let accumulated = p.push;
            p.push = (p.push - separation).clamp(0.0, p.push_limit);
            let push = p.push - accumulated;
            delta += push * p.plane.normal;
            total_push += push.abs();
        }
        if total_push < LINEAR_SLOP {
            break;
        }
        iteration += 1;
    }
    PlaneSolverResult {
        translation: delta,
        iteration_count: iteration,
    }
}

/// `vector` less its parts into the planes that pushed in the last [`solve_planes`] and clip
/// velocity (Box2D's `b2ClipVector`): a velocity that runs into the floor keeps its part
/// along the floor.
pub fn clip_vector(vector: Vec2, planes: &[CollisionPlane]) -> Vec2 {
    let mut v = vector;
    for p in planes {
        if p.push == 0.0 || !p.clip_velocity {
            continue;
        }
        v -= v.dot(p.plane.normal).min(0.0) * p.plane.normal;
    }
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plane(nx: f32, ny: f32, offset: f32) -> CollisionPlane {
        CollisionPlane::new(Plane {
            normal: Vec2::new(nx, ny).normalize(),
            offset,
        })
    }

    // Each expected figure is solved by hand below; 1e-6 m is a few f32 roundings of
    // numbers of order 1.
    const EXACT: f32 = 1e-6;

    #[test]
    fn a_floor_lifts_the_mover_out_to_a_slop_inside_and_keeps_its_sideways_motion() {
        // Floor normal +y, the mover 0.1 m inside: the plane pushes until
        // n·δ − 0.1 + slop = 0, so δy = 0.1 − 0.005 = 0.095; δx is untouched.
        let mut planes = [plane(0.0, 1.0, 0.1)];
        let r = solve_planes(Vec2::new(1.0, -0.5), &mut planes);
        assert!(
            (r.translation - Vec2::new(1.0, 0.095)).length() < EXACT,
            "{r:?}"
        );
        assert!((planes[0].push - 0.595).abs() < EXACT);
        // One plane converges in a sweep; the next confirms it.
        assert_eq!(r.iteration_count, 1);
        // A velocity into the floor keeps its part along it.
        let v = clip_vector(Vec2::new(3.0, -2.0), &planes);
        assert!((v - Vec2::new(3.0, 0.0)).length() < EXACT);
        // A velocity away from it is kept whole.
        assert_eq!(
            clip_vector(Vec2::new(3.0, 2.0), &planes),
            Vec2::new(3.0, 2.0)
        );
    }

    #[test]
    fn a_corner_stops_the_mover_a_slop_into_both_planes() {
        // Floor (normal +y) and a wall on the right (normal −x), both just touching: the
        // solution has n·δ = −slop for each, δ = (0.005, −0.005).
        let mut planes = [plane(0.0, 1.0, 0.0), plane(-1.0, 0.0, 0.0)];
        let r = solve_planes(Vec2::new(1.0, -1.0), &mut planes);
        assert!(
            (r.translation - Vec2::new(0.005, -0.005)).length() < EXACT,
            "{r:?}"
        );
        assert_eq!(clip_vector(Vec2::new(2.0, -3.0), &planes), Vec2::ZERO);
    }

    #[test]
    fn a_ramp_turns_horizontal_motion_up_its_slope() {
        // A 45° ramp rising to the right (normal (−1, 1)/√2) touching the mover: moving
        // (1, 0), n·δ = −0.7071 must become −slop, a push of 0.7071 − 0.005 = 0.70211 along
        // n: δ = (1, 0) + 0.70211·(−0.70711, 0.70711) = (0.50353, 0.49647).
        let mut planes = [plane(-1.0, 1.0, 0.0)];
        let r = solve_planes(Vec2::new(1.0, 0.0), &mut planes);
        let s = std::f32::consts::FRAC_1_SQRT_2;
        let push = s - LINEAR_SLOP;
        let expected = Vec2::new(1.0 - push * s, push * s);
        assert!(
            (r.translation - expected).length() < EXACT,
            "{r:?} {expected}"
        );
    }

    #[test]
    fn a_push_limit_lets_the_mover_sink_past_what_it_may_push() {
        // The plane may push 0.05 m at most: the mover, 0.2 m inside and moving down 0.1,
        // rises by only 0.05 of what it needs and ends at δy = −0.1 + 0.05.
        let mut planes = [CollisionPlane {
            push_limit: 0.05,
            ..plane(0.0, 1.0, 0.2)
        }];
        let r = solve_planes(Vec2::new(0.0, -0.1), &mut planes);
        assert!(
            (r.translation - Vec2::new(0.0, -0.05)).length() < EXACT,
            "{r:?}"
        );
        assert_eq!(planes[0].push, 0.05);
        // A plane that pushed nothing, or does not clip, leaves a velocity alone.
        let mut idle = [plane(0.0, 1.0, -1.0)];
        solve_planes(Vec2::ZERO, &mut idle);
        assert_eq!(idle[0].push, 0.0);
        assert_eq!(
            clip_vector(Vec2::new(0.0, -1.0), &idle),
            Vec2::new(0.0, -1.0)
        );
        planes[0].clip_velocity = false;
        assert_eq!(
            clip_vector(Vec2::new(0.0, -1.0), &planes),
            Vec2::new(0.0, -1.0)
        );
    }

    #[test]
    fn two_planes_at_an_angle_converge_within_the_iteration_bound() {
        // A V-shaped floor (normals 60° apart) under a mover pressed into both: the
        // Gauss-Seidel sweeps converge (pushes under a slop) before the bound of 20.
        let mut planes = [plane(-0.5, 1.0, 0.05), plane(0.5, 1.0, 0.05)];
        let r = solve_planes(Vec2::new(0.3, -0.4), &mut planes);
        assert!(r.iteration_count < PLANE_ITERATIONS, "{r:?}");
        for p in &planes {
            // Each plane satisfied to within the tolerance the loop stops at.
            assert!(p.plane.separation(r.translation) > -LINEAR_SLOP - LINEAR_SLOP);
        }
    }
}
