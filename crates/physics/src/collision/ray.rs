//! Ray casts against one shape, in the shape's own frame (Box2D v3's `b2RayCast*` in
//! `geometry.c`). A ray is `origin + t · translation` for t in [0, `max_fraction`]; a ray that
//! starts inside a shape with area reports no hit (it never enters it).

use glam::Vec2;

use crate::math::{cross, dot, normalize_and_length, right_perp};
use crate::shape::{Capsule, Polygon, Segment, Shape};

/// Where a ray first meets a shape.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayHitLocal {
    /// The ray's parameter at the hit, in [0, max_fraction].
    pub fraction: f32,
    /// The hit point.
    pub point: Vec2,
    /// The surface normal there, outward (towards the ray's origin side).
    pub normal: Vec2,
}

/// A ray: from `origin` along `translation`, up to `max_fraction` of it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Start.
    pub origin: Vec2,
    /// Direction and length (the point at fraction 1 is `origin + translation`).
    pub translation: Vec2,
    /// Farthest fraction of `translation` to look.
    pub max_fraction: f32,
}

/// Casts `ray` against `shape` (both in the shape's frame).
pub fn ray_cast(shape: &Shape, ray: &Ray) -> Option<RayHitLocal> {
    match shape {
        Shape::Circle(c) => ray_circle(c.radius, Vec2::ZERO, ray),
        Shape::Capsule(c) => ray_capsule(c, ray),
        Shape::Polygon(p) if p.radius == 0.0 => ray_polygon(p, ray),
        Shape::Polygon(p) => ray_rounded(p, ray),
        Shape::Segment(s) => ray_segment(s, ray, false),
        Shape::ChainSegment(c) => ray_segment(&c.segment, ray, true),
    }
}

/// A disc of `radius` at `center` (Box2D's `b2RayCastCircle`): the nearer root of
/// |s + t d|² = r² with s the origin relative to the centre and d the unit direction.
fn ray_circle(radius: f32, center: Vec2, ray: &Ray) -> Option<RayHitLocal> {
    let s = ray.origin - center;
    let (d, length) = normalize_and_length(ray.translation);
    if length == 0.0 {
        return None;
    }
    // The point of the line nearest the centre, and its distance squared.
    let t = -dot(s, d);
    let c = s + d * t;
    let cc = dot(c, c);
    let rr = radius * radius;
    if cc > rr {
        return None;
    }
    let fraction = t - (rr - cc).sqrt();
    if fraction < 0.0 || ray.max_fraction * length < fraction {
        return None;
    }
    let normal = normalize_and_length(s + d * fraction).0;
    Some(RayHitLocal {
        fraction: fraction / length,
        point: center + normal * radius,
        normal,
    })
}

/// A convex polygon without rounding (Box2D's `b2RayCastPolygon`, Cyrus–Beck clipping of the
/// ray against each edge's half-plane).
fn ray_polygon(p: &Polygon, ray: &Ray) -> Option<RayHitLocal> {
    let (mut lower, mut upper) = (0.0f32, ray.max_fraction);
    let mut index = None;
    for i in 0..p.count {
        // p = origin + t d is inside edge i's half-plane where dot(n, v - p) >= 0.
        let numerator = dot(p.normals[i], p.vertices[i] - ray.origin);
        let denominator = dot(p.normals[i], ray.translation);
        if denominator == 0.0 {
            if numerator < 0.0 {
                return None;
            }
        } else if denominator < 0.0 && numerator < lower * denominator {
            // Entering this half-plane: the lower bound rises.
            lower = numerator / denominator;
            index = Some(i);
        } else if denominator > 0.0 && numerator < upper * denominator {
            upper = numerator / denominator;
        }
        if upper < lower {
            return None;
        }
    }
    // No entering edge: the ray starts inside.
    let i = index?;
    Some(RayHitLocal {
        fraction: lower,
        point: ray.origin + ray.translation * lower,
        normal: p.normals[i],
    })
}

/// A capsule: its core segment rounded by its radius.
fn ray_capsule(c: &Capsule, ray: &Ray) -> Option<RayHitLocal> {
    ray_rounded(&Polygon::capsule(c.center1, c.center2, c.radius), ray)
}

/// A polygon rounded by its radius (a capsule is one of two vertices): the shape's boundary is
/// each edge pushed out along its normal by the radius, and an arc about each vertex. A ray
/// from outside first meets the boundary where it first meets one of those edges (from
/// outside) or one of the vertices' discs, each of which lies inside the shape; so the
/// nearest of those hits is the hit.
fn ray_rounded(p: &Polygon, ray: &Ray) -> Option<RayHitLocal> {
    if inside_rounded(p, ray.origin) {
        return None;
    }
    let n = p.count;
    let mut best: Option<RayHitLocal> = None;
    let mut keep = |hit: Option<RayHitLocal>| {
        if let Some(h) = hit
            && best.is_none_or(|b| h.fraction < b.fraction)
        {
            best = Some(h);
        }
    };
    for i in 0..n {
        let offset = p.normals[i] * p.radius;
        // A polygon of two vertices (a capsule) has its two sides as edges 0 → 1 and 1 → 0.
        let (a, b) = (p.vertices[i], p.vertices[(i + 1) % n]);
        let side = Segment {
            point1: a + offset,
            point2: b + offset,
        };
        keep(ray_segment(&side, ray, false).filter(|h| dot(h.normal, p.normals[i]) > 0.0));
        keep(ray_circle(p.radius, a, ray));
    }
    best
}

/// Whether `point` lies within `p.radius` of polygon `p` (for two vertices, of its segment:
/// the half-planes of a segment's two sides hold its whole line).
fn inside_rounded(p: &Polygon, point: Vec2) -> bool {
    let n = p.count;
    let in_core = n > 2 && (0..n).all(|k| dot(p.normals[k], point - p.vertices[k]) <= 0.0);
    in_core
        || (0..n).any(|k| {
            let (a, b) = (p.vertices[k], p.vertices[(k + 1) % n]);
            let t = (dot(point - a, b - a) / dot(b - a, b - a)).clamp(0.0, 1.0);
            let d = point - (a + (b - a) * t);
            dot(d, d) <= p.radius * p.radius
        })
}

/// A segment (Box2D's `b2RayCastSegment`); `one_sided`: only from its right-hand side (a
/// chain segment's pushing side, that of (dy, −dx)), and a ray starting behind it misses.
fn ray_segment(s: &Segment, ray: &Ray, one_sided: bool) -> Option<RayHitLocal> {
    let (v1, v2) = (s.point1, s.point2);
    if one_sided && cross(ray.origin - v1, v2 - v1) < 0.0 {
        return None;
    }
    let (e, length) = normalize_and_length(v2 - v1);
    if length == 0.0 {
        return None;
    }
    let mut normal = right_perp(e);
    // origin + t d meets the segment's line where dot(normal, p - v1) = 0.
    let numerator = dot(normal, v1 - ray.origin);
    let denominator = dot(normal, ray.translation);
    if denominator == 0.0 {
        return None;
    }
    let t = numerator / denominator;
    if t < 0.0 || ray.max_fraction < t {
        return None;
    }
    let point = ray.origin + ray.translation * t;
    let along = dot(point - v1, e);
    if along < 0.0 || length < along {
        return None;
    }
    // The side the ray came from.
    if numerator > 0.0 {
        normal = -normal;
    }
    Some(RayHitLocal {
        fraction: t,
        point: v1 + e * along,
        normal,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shape::{ChainSegment, Circle};

    fn ray(ox: f32, oy: f32, dx: f32, dy: f32) -> Ray {
        Ray {
            origin: Vec2::new(ox, oy),
            translation: Vec2::new(dx, dy),
            max_fraction: 1.0,
        }
    }

    /// Hits to within 1e-5 (f32 arithmetic on values of order 1).
    #[track_caller]
    fn near(hit: Option<RayHitLocal>, fraction: f32, point: [f32; 2], normal: [f32; 2]) {
        let h = hit.expect("a hit");
        assert!((h.fraction - fraction).abs() < 1e-5, "{h:?}");
        assert!((h.point - Vec2::from(point)).length() < 1e-5, "{h:?}");
        assert!((h.normal - Vec2::from(normal)).length() < 1e-5, "{h:?}");
    }

    #[test]
    fn a_ray_meets_a_circle_at_its_near_side_and_misses_from_inside() {
        let disc = Shape::Circle(Circle { radius: 1.0 });
        near(
            ray_cast(&disc, &ray(-3.0, 0.0, 4.0, 0.0)),
            0.5,
            [-1.0, 0.0],
            [-1.0, 0.0],
        );
        // Grazing above: the line passes at 1.5 > r.
        assert!(ray_cast(&disc, &ray(-3.0, 1.5, 4.0, 0.0)).is_none());
        // Too short: it stops 0.5 before the disc.
        assert!(ray_cast(&disc, &ray(-3.0, 0.0, 1.5, 0.0)).is_none());
        assert!(ray_cast(&disc, &ray(0.0, 0.0, 4.0, 0.0)).is_none());
    }

    #[test]
    fn a_ray_meets_a_box_on_the_face_it_enters() {
        let b = Shape::Polygon(Polygon::new_box(1.0, 0.5));
        near(
            ray_cast(&b, &ray(0.0, 3.0, 0.0, -5.0)),
            0.5,
            [0.0, 0.5],
            [0.0, 1.0],
        );
        near(
            ray_cast(&b, &ray(4.0, 0.25, -6.0, 0.0)),
            0.5,
            [1.0, 0.25],
            [1.0, 0.0],
        );
        assert!(
            ray_cast(&b, &ray(0.0, 0.0, 5.0, 0.0)).is_none(),
            "from inside"
        );
        assert!(
            ray_cast(&b, &ray(-3.0, 0.6, 6.0, 0.0)).is_none(),
            "above it"
        );
    }

    #[test]
    fn a_rounded_box_is_met_on_its_pushed_out_face_and_its_corner_arcs() {
        let mut p = Polygon::new_box(1.0, 1.0);
        p.radius = 0.5;
        let rounded = Shape::Polygon(p);
        // Straight down onto the top face, pushed out to y = 1.5.
        near(
            ray_cast(&rounded, &ray(0.0, 4.0, 0.0, -5.0)),
            0.5,
            [0.0, 1.5],
            [0.0, 1.0],
        );
        // Along the diagonal onto the corner arc: the point at (1, 1) + 0.5 (1, 1)/√2.
        let k = 0.5 / 2f32.sqrt();
        let start = 3.0;
        let hit = ray_cast(&rounded, &ray(start, start, -start, -start));
        let fraction = (start - 1.0 - k) / start;
        near(
            hit,
            fraction,
            [1.0 + k, 1.0 + k],
            [0.5f32.sqrt(), 0.5f32.sqrt()],
        );
        // A level ray at y = 1.45 from the right meets the top-right arc (which reaches up
        // to y = 1.5); at 1.55 it passes over the shape.
        assert!(ray_cast(&rounded, &ray(4.0, 1.45, -6.0, 0.0)).is_some());
        assert!(ray_cast(&rounded, &ray(4.0, 1.55, -6.0, 0.0)).is_none());
        assert!(
            ray_cast(&rounded, &ray(1.2, 1.2, 1.0, 0.0)).is_none(),
            "from inside"
        );
    }

    #[test]
    fn a_capsule_is_met_on_its_side_and_its_cap() {
        let c = Shape::Capsule(Capsule {
            center1: Vec2::new(-1.0, 0.0),
            center2: Vec2::new(1.0, 0.0),
            radius: 0.5,
        });
        near(
            ray_cast(&c, &ray(0.5, -2.0, 0.0, 4.0)),
            0.375,
            [0.5, -0.5],
            [0.0, -1.0],
        );
        near(
            ray_cast(&c, &ray(3.0, 0.0, -4.0, 0.0)),
            0.375,
            [1.5, 0.0],
            [1.0, 0.0],
        );
    }

    #[test]
    fn a_segment_is_met_from_both_sides_and_a_chain_segment_from_its_right_only() {
        let s = Segment {
            point1: Vec2::new(-1.0, 0.0),
            point2: Vec2::new(1.0, 0.0),
        };
        near(
            ray_cast(&Shape::Segment(s), &ray(0.0, 2.0, 0.0, -4.0)),
            0.5,
            [0.0, 0.0],
            [0.0, 1.0],
        );
        near(
            ray_cast(&Shape::Segment(s), &ray(0.0, -2.0, 0.0, 4.0)),
            0.5,
            [0.0, 0.0],
            [0.0, -1.0],
        );
        // From −x to +x, a chain segment's right-hand side is below (0, −1).
        let chain = Shape::ChainSegment(ChainSegment {
            ghost1: Vec2::new(-2.0, 0.0),
            segment: s,
            ghost2: Vec2::new(2.0, 0.0),
        });
        near(
            ray_cast(&chain, &ray(0.0, -2.0, 0.0, 4.0)),
            0.5,
            [0.0, 0.0],
            [0.0, -1.0],
        );
        assert!(ray_cast(&chain, &ray(0.0, 2.0, 0.0, -4.0)).is_none());
        assert!(
            ray_cast(&Shape::Segment(s), &ray(2.0, 1.0, 0.0, -4.0)).is_none(),
            "past its end"
        );
    }
}
