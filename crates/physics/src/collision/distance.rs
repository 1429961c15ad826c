//! Distance between convex shapes (GJK) and time of impact of two moving shapes
//! (conservative advancement), for continuous collision.
//!
//! GJK: Gilbert, Johnson and Keerthi, "A fast procedure for computing the distance between
//! complex objects in three-dimensional space", IEEE J. Robotics and Automation 4(2), 1988,
//! in the 2D form with barycentric sub-simplex solves of Box2D v3's `distance.c` (Catto,
//! "Computing Distance", GDC 2010). Time of impact: conservative advancement (Mirtich,
//! "Impulse-based Dynamic Simulation of Rigid Body Systems", PhD thesis, Berkeley 1996,
//! ch. 2): from the closest points' normal, no point of the moving shapes can close the gap
//! faster than a bound on their speed along it, so stepping the time by gap / bound never
//! passes the impact.

use glam::Vec2;

use crate::LINEAR_SLOP;
use crate::MAX_POLYGON_VERTICES;
use crate::math::{Rot, Transform, atan2, cross, dot};
use crate::shape::Shape;

/// A convex shape as GJK sees it: a convex hull of points, rounded by a radius.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Proxy {
    points: [Vec2; MAX_POLYGON_VERTICES],
    count: usize,
    /// The rounding radius (a circle's or a capsule's radius, a rounded polygon's).
    pub radius: f32,
}

impl Proxy {
    /// `shape`'s proxy, with its points placed by `local` (the shape's frame in the frame the
    /// caller moves: a body's centre of mass).
    pub fn of(shape: &Shape, local: Transform) -> Proxy {
        let (points, radius): (&[Vec2], f32) = match shape {
            Shape::Circle(c) => (&[Vec2::ZERO], c.radius),
            Shape::Capsule(c) => (&[c.center1, c.center2], c.radius),
            Shape::Polygon(p) => (p.points(), p.radius),
            Shape::Segment(s) => (&[s.point1, s.point2], 0.0),
            Shape::ChainSegment(c) => (&[c.segment.point1, c.segment.point2], 0.0),
        };
        Proxy::points(points, radius, local)
    }

    /// The hull of `points` (at most 8) placed by `local`, rounded by `radius`.
    pub fn points(points: &[Vec2], radius: f32, local: Transform) -> Proxy {
        let mut p = Proxy {
            points: [Vec2::ZERO; MAX_POLYGON_VERTICES],
            count: points.len().min(MAX_POLYGON_VERTICES),
            radius,
        };
        for (slot, &v) in p.points.iter_mut().zip(points) {
            *slot = local.apply(v);
        }
        p
    }

    /// Its core's points (the hull it rounds by `radius`).
    pub fn core(&self) -> &[Vec2] {
        &self.points[..self.count]
    }

    /// The farthest of its points from its frame's origin (a bound on how far a point of the
    /// core moves when the frame turns by an angle).
    pub fn reach(&self) -> f32 {
        self.points[..self.count]
            .iter()
            .map(|p| p.length())
            .fold(0.0, f32::max)
    }

    /// The index of the point farthest along `d`.
    fn support(&self, d: Vec2) -> usize {
        let mut best = 0;
        let mut best_value = dot(self.points[0], d);
        for i in 1..self.count {
            let value = dot(self.points[i], d);
            if value > best_value {
                best = i;
                best_value = value;
            }
        }
        best
    }
}

/// The closest points of two proxies' cores (without their radii) and their distance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Closest {
    /// On A's core, in the world.
    pub point_a: Vec2,
    /// On B's core, in the world.
    pub point_b: Vec2,
    /// Between the cores; 0 when they overlap.
    pub distance: f32,
}

/// A vertex of the simplex: a point of the Minkowski difference B − A, from the points of A
/// and B it came from.
#[derive(Clone, Copy, Debug, Default)]
struct Vertex {
    wa: Vec2,
    wb: Vec2,
    w: Vec2,
    /// Barycentric weight in the closest point.
    a: f32,
    index_a: usize,
    index_b: usize,
}

/// Most GJK iterations (Box2D's bound; 2D converges in a handful).
const GJK_ITERATIONS: usize = 20;

/// The distance between the cores of `a` at `xf_a` and `b` at `xf_b` (GJK).
pub fn distance(a: &Proxy, xf_a: Transform, b: &Proxy, xf_b: Transform) -> Closest {
    // Work in A's frame: B's points moved there once.
    let rel = xf_a.inv_mul(xf_b);
    let mut b_local = *b;
    for p in &mut b_local.points[..b.count] {
        *p = rel.apply(*p);
    }
    let b = &b_local;
    let vertex = |ia: usize, ib: usize| Vertex {
        wa: a.points[ia],
        wb: b.points[ib],
        w: b.points[ib] - a.points[ia],
        a: 1.0,
        index_a: ia,
        index_b: ib,
    };
    let mut v = [vertex(0, 0), Vertex::default(), Vertex::default()];
    let mut count = 1;
    for _ in 0..GJK_ITERATIONS {
        let saved = [
            (v[0].index_a, v[0].index_b),
            (v[1].index_a, v[1].index_b),
            (v[2].index_a, v[2].index_b),
        ];
        let saved_count = count;
        match count {
            2 => solve2(&mut v, &mut count),
            3 => solve3(&mut v, &mut count),
            _ => {}
        }
        // A triangle holds the origin: the cores overlap.
        if count == 3 {
            break;
        }
        let d = search_direction(&v, count);
        // The origin is on the simplex (touching cores): no direction to search.
        if dot(d, d) < f32::EPSILON * f32::EPSILON {
            break;
        }
        // The support point of B − A along d.
        let ia = a.support(-d);
        let ib = b.support(d);
        // A repeated vertex: no progress, the simplex is the closest feature.
        if saved[..saved_count].contains(&(ia, ib)) {
            break;
        }
        v[count] = vertex(ia, ib);
        count += 1;
    }
    let (pa, pb) = witness_points(&v, count);
    Closest {
        point_a: xf_a.apply(pa),
        point_b: xf_a.apply(pb),
        distance: (pb - pa).length(),
    }
}

/// Towards the origin from the simplex (perpendicular to a segment, on the origin's side, for
/// better accuracy than the negated closest point).
fn search_direction(v: &[Vertex; 3], count: usize) -> Vec2 {
    if count == 1 {
        return -v[0].w;
    }
    let e = v[1].w - v[0].w;
    if cross(e, -v[0].w) > 0.0 {
        Vec2::new(-e.y, e.x)
    } else {
        Vec2::new(e.y, -e.x)
    }
}

fn witness_points(v: &[Vertex; 3], count: usize) -> (Vec2, Vec2) {
    match count {
        1 => (v[0].wa, v[0].wb),
        2 => (
            v[0].wa * v[0].a + v[1].wa * v[1].a,
            v[0].wb * v[0].a + v[1].wb * v[1].a,
        ),
        _ => {
            let p = v[0].wa * v[0].a + v[1].wa * v[1].a + v[2].wa * v[2].a;
            (p, p)
        }
    }
}

/// The closest point of segment w1–w2 to the origin, as barycentric weights; drops the
/// vertex whose region holds it.
fn solve2(v: &mut [Vertex; 3], count: &mut usize) {
    let (w1, w2) = (v[0].w, v[1].w);
    let e12 = w2 - w1;
    // Region of w1.
    let d12_2 = -dot(w1, e12);
    if d12_2 <= 0.0 {
        v[0].a = 1.0;
        *count = 1;
        return;
    }
    // Region of w2.
    let d12_1 = dot(w2, e12);
    if d12_1 <= 0.0 {
        v[1].a = 1.0;
        v[0] = v[1];
        *count = 1;
        return;
    }
    let inv = 1.0 / (d12_1 + d12_2);
    v[0].a = d12_1 * inv;
    v[1].a = d12_2 * inv;
    *count = 2;
}

/// The closest point of triangle w1 w2 w3 to the origin, by its Voronoi regions.
fn solve3(v: &mut [Vertex; 3], count: &mut usize) {
    let (w1, w2, w3) = (v[0].w, v[1].w, v[2].w);
    let e12 = w2 - w1;
    let (d12_1, d12_2) = (dot(w2, e12), -dot(w1, e12));
    let e13 = w3 - w1;
    let (d13_1, d13_2) = (dot(w3, e13), -dot(w1, e13));
    let e23 = w3 - w2;
    let (d23_1, d23_2) = (dot(w3, e23), -dot(w2, e23));
    let n123 = cross(e12, e13);
    let d123_1 = n123 * cross(w2, w3);
    let d123_2 = n123 * cross(w3, w1);
    let d123_3 = n123 * cross(w1, w2);
    if d12_2 <= 0.0 && d13_2 <= 0.0 {
        v[0].a = 1.0;
        *count = 1;
        return;
    }
    if d12_1 > 0.0 && d12_2 > 0.0 && d123_3 <= 0.0 {
        let inv = 1.0 / (d12_1 + d12_2);
        v[0].a = d12_1 * inv;
        v[1].a = d12_2 * inv;
        *count = 2;
        return;
    }
    if d13_1 > 0.0 && d13_2 > 0.0 && d123_2 <= 0.0 {
        let inv = 1.0 / (d13_1 + d13_2);
        v[0].a = d13_1 * inv;
        v[2].a = d13_2 * inv;
        v[1] = v[2];
        *count = 2;
        return;
    }
    if d12_1 <= 0.0 && d23_2 <= 0.0 {
        v[1].a = 1.0;
        v[0] = v[1];
        *count = 1;
        return;
    }
    if d13_1 <= 0.0 && d23_1 <= 0.0 {
        v[2].a = 1.0;
        v[0] = v[2];
        *count = 1;
        return;
    }
    if d23_1 > 0.0 && d23_2 > 0.0 && d123_1 <= 0.0 {
        let inv = 1.0 / (d23_1 + d23_2);
        v[1].a = d23_1 * inv;
        v[2].a = d23_2 * inv;
        v[0] = v[2];
        *count = 2;
        return;
    }
    let inv = 1.0 / (d123_1 + d123_2 + d123_3);
    v[0].a = d123_1 * inv;
    v[1].a = d123_2 * inv;
    v[2].a = d123_3 * inv;
    *count = 3;
}

/// A body's motion over a step, as its centre of mass's pose at the start and at the end;
/// between them the centre moves in a straight line and the rotation turns at the rate of
/// its normalised linear blend (Box2D's `b2Sweep` and `b2GetSweepTransform`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sweep {
    /// Centre of mass at the start.
    pub c0: Vec2,
    /// Centre of mass at the end.
    pub c1: Vec2,
    /// Rotation at the start.
    pub q0: Rot,
    /// Rotation at the end.
    pub q1: Rot,
}

impl Sweep {
    /// A body that does not move.
    pub fn still(xf: Transform) -> Sweep {
        Sweep {
            c0: xf.p,
            c1: xf.p,
            q0: xf.q,
            q1: xf.q,
        }
    }

    /// The centre's pose at fraction `t` of the step.
    pub fn at(&self, t: f32) -> Transform {
        let q = Rot {
            c: (1.0 - t) * self.q0.c + t * self.q1.c,
            s: (1.0 - t) * self.q0.s + t * self.q1.s,
        }
        .normalize();
        Transform {
            p: self.c0 * (1.0 - t) + self.c1 * t,
            q,
        }
    }

    /// The most its rotation turns per unit of `t`: the normalised blend of two unit
    /// rotations an angle Δ apart turns fastest midway, at 2 tan(Δ/2).
    fn max_turn_rate(&self) -> f32 {
        let turn = self.q0.inv_mul(self.q1);
        let half = 0.5 * atan2(turn.s, turn.c).abs();
        2.0 * (half.sin() / half.cos().max(1e-6))
    }
}

/// What [`time_of_impact`] found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Impact {
    /// The shapes come within the target separation at this fraction of the step, in
    /// (0, max_fraction).
    At(f32),
    /// They are within it already at the start.
    Overlapping,
    /// They stay apart up to `max_fraction`.
    Apart,
}

/// Most advancement iterations; a rotating shape grazing another converges slowest.
const TOI_ITERATIONS: usize = 30;

/// When shapes `a` and `b`, moving by their sweeps, first come within Box2D's target
/// separation (their rounded surfaces a linear slop into each other, or cores a slop apart
/// for sharp shapes: `b2TimeOfImpact`'s target), by conservative advancement.
pub fn time_of_impact(
    a: &Proxy,
    sweep_a: &Sweep,
    b: &Proxy,
    sweep_b: &Sweep,
    max_fraction: f32,
) -> Impact {
    let total_radius = a.radius + b.radius;
    let target = LINEAR_SLOP.max(total_radius - LINEAR_SLOP);
    let tolerance = 0.25 * LINEAR_SLOP;
    let (da, db) = (sweep_a.c1 - sweep_a.c0, sweep_b.c1 - sweep_b.c0);
    let turn = sweep_a.max_turn_rate() * a.reach() + sweep_b.max_turn_rate() * b.reach();
    let mut t = 0.0f32;
    for _ in 0..TOI_ITERATIONS {
        let c = distance(a, sweep_a.at(t), b, sweep_b.at(t));
        if c.distance < target + tolerance {
            return if t == 0.0 {
                Impact::Overlapping
            } else {
                Impact::At(t)
            };
        }
        // No point of B approaches A along the closest points' normal faster than this (per
        // unit of t): the cores' gap cannot close sooner than gap / bound.
        let n = (c.point_b - c.point_a) / c.distance;
        let bound = dot(n, da - db) + turn;
        if bound <= 0.0 {
            return Impact::Apart;
        }
        // Aim for the middle of the tolerance band, so the next test lands inside it.
        t += (c.distance - target) / bound;
        if t >= max_fraction {
            return Impact::Apart;
        }
    }
    // Still advancing after every iteration (a graze): stop here, short of any impact.
    Impact::At(t)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shape::{Circle, Polygon};

    fn at(x: f32, y: f32, angle: f32) -> Transform {
        Transform {
            p: Vec2::new(x, y),
            q: Rot::from_angle(angle),
        }
    }

    #[test]
    fn gjk_finds_the_distance_between_boxes_circles_and_segments() {
        let unit = Proxy::of(
            &Shape::Polygon(Polygon::new_box(0.5, 0.5)),
            Transform::IDENTITY,
        );
        // Side by side, 1 m of gap between faces.
        let c = distance(&unit, at(0.0, 0.0, 0.0), &unit, at(2.0, 0.3, 0.0));
        assert!((c.distance - 1.0).abs() < 1e-6, "{c:?}");
        // Corner to corner along the diagonal: the gap between (0.5, 0.5) and (1.5, 1.5).
        let c = distance(&unit, at(0.0, 0.0, 0.0), &unit, at(2.0, 2.0, 0.0));
        assert!((c.distance - 2f32.sqrt()).abs() < 1e-6, "{c:?}");
        assert!((c.point_a - Vec2::new(0.5, 0.5)).length() < 1e-6);
        // A box turned 45° whose corner points at the other's face: the gap is
        // 2 − 0.5 − √2/2.
        let c = distance(
            &unit,
            at(0.0, 0.0, 0.0),
            &unit,
            at(2.0, 0.0, std::f32::consts::FRAC_PI_4),
        );
        assert!((c.distance - (1.5 - 0.5f32.sqrt())).abs() < 1e-5, "{c:?}");
        // Overlapping: 0.
        let c = distance(&unit, at(0.0, 0.0, 0.0), &unit, at(0.5, 0.2, 0.3));
        assert_eq!(c.distance, 0.0);
        // A circle's core is its centre (its radius is left to the caller).
        let disc = Proxy::of(&Shape::Circle(Circle { radius: 0.25 }), Transform::IDENTITY);
        let c = distance(&unit, at(0.0, 0.0, 0.0), &disc, at(0.0, 3.0, 0.0));
        assert!(
            (c.distance - 2.5).abs() < 1e-6 && disc.radius == 0.25,
            "{c:?}"
        );
    }

    #[test]
    fn a_fast_disc_meets_a_thin_wall_where_the_closed_form_says() {
        // A disc of radius 0.1 crossing 10 m in a step towards a wall 5 cm thick at x = 5:
        // its surface reaches x = 4.975 when its centre is at 4.875, t = 0.4875; the target
        // leaves it a slop into the wall, so t ≈ (4.875 + 0.005) / 10.
        let wall = Proxy::of(
            &Shape::Polygon(Polygon::new_box(0.025, 2.0)),
            Transform::IDENTITY,
        );
        let disc = Proxy::of(&Shape::Circle(Circle { radius: 0.1 }), Transform::IDENTITY);
        let still = Sweep::still(at(5.0, 0.0, 0.0));
        let fly = Sweep {
            c0: Vec2::ZERO,
            c1: Vec2::new(10.0, 0.0),
            q0: Rot::IDENTITY,
            q1: Rot::IDENTITY,
        };
        let Impact::At(t) = time_of_impact(&wall, &still, &disc, &fly, 1.0) else {
            panic!("no impact");
        };
        let expected = (4.875 + LINEAR_SLOP) / 10.0;
        assert!(
            (t - expected).abs() < 0.25 * LINEAR_SLOP / 10.0 + 1e-6,
            "{t} vs {expected}"
        );
        // Going the other way, or stopping short, it never meets the wall.
        let away = Sweep {
            c1: Vec2::new(-10.0, 0.0),
            ..fly
        };
        assert_eq!(
            time_of_impact(&wall, &still, &disc, &away, 1.0),
            Impact::Apart
        );
        assert_eq!(
            time_of_impact(&wall, &still, &disc, &fly, 0.4),
            Impact::Apart
        );
    }

    #[test]
    fn a_spinning_stick_is_caught_before_it_sweeps_through_a_post() {
        // A stick 2 m long centred at the origin turning a quarter turn in a step, and a
        // thin post at (0.8, 0.5): the stick's tip, at 1 m, passes the post's corner
        // partway through the turn. At the impact time the two must be (nearly) touching,
        // and a little earlier clearly apart.
        let stick = Proxy::of(
            &Shape::Polygon(Polygon::new_box(1.0, 0.02)),
            Transform::IDENTITY,
        );
        let post = Proxy::of(
            &Shape::Polygon(Polygon::new_box(0.02, 0.02)),
            Transform::IDENTITY,
        );
        let turn = Sweep {
            c0: Vec2::ZERO,
            c1: Vec2::ZERO,
            q0: Rot::IDENTITY,
            q1: Rot::from_angle(std::f32::consts::FRAC_PI_2),
        };
        let still = Sweep::still(at(0.8, 0.5, 0.0));
        let Impact::At(t) = time_of_impact(&post, &still, &stick, &turn, 1.0) else {
            panic!("no impact");
        };
        let gap = |t: f32| distance(&post, still.at(t), &stick, turn.at(t)).distance;
        assert!(
            gap(t) <= LINEAR_SLOP + 0.25 * LINEAR_SLOP + 1e-6,
            "gap {}",
            gap(t)
        );
        assert!(gap(t) > 0.0);
        assert!(gap(0.9 * t) > gap(t));
        // The closed form: the stick's upper face (0.02 off its axis) first meets the post's
        // lower-right corner (0.82, 0.48), the one at the smallest angle, when the axis has
        // turned to atan2(0.48, 0.82) less asin(0.02 / |corner|).
        let corner = Vec2::new(0.82, 0.48);
        let angle = corner.y.atan2(corner.x) - (0.02 / corner.length()).asin();
        let closed = angle / std::f32::consts::FRAC_PI_2;
        // Within a few slops of turning at the tip (1 m): nlerp's pace differs from a
        // uniform turn by under 0.03 of a quarter turn at these angles, so compare angles.
        let turned = |t: f32| {
            let q = turn.at(t).q;
            q.s.atan2(q.c)
        };
        assert!(
            (turned(t) - angle).abs() < 4.0 * LINEAR_SLOP,
            "turned {} vs {angle} (t {t}, uniform {closed})",
            turned(t)
        );
    }
}
