//! Contact manifolds for each shape pair.
//!
//! Shape A is the one later in Box2D's order of shape types (circle, capsule, polygon,
//! segment, chain segment): circle–circle, capsule–circle, capsule–capsule, polygon–circle,
//! polygon–capsule, polygon–polygon, segment–{circle, capsule, polygon} and chain
//! segment–{circle, capsule, polygon}. Segments never meet segments. Two capsules (or a
//! segment and a capsule) meet by the closest points of their cores, clipped to two points
//! where the cores run side by side; against a polygon, capsules and segments go through the
//! polygon routines as two-vertex polygons with a radius ([`Polygon::capsule`]); rounded
//! polygons carry their radius through them.
//!
//! The algorithms follow Box2D v3 (`manifold.c`): points lie midway between the two
//! surfaces with a signed separation, the normal points from A to B, and every point carries
//! a feature id (reference and incident vertex or edge indices) so the solver can carry its
//! impulses over to the next step. Points are kept while their separation is within
//! `max_distance` (the speculative margin), so bodies meet without overlapping.

use glam::Vec2;

use crate::LINEAR_SLOP;
use crate::math::{Transform, dot, normalize_and_length, right_perp};
use crate::shape::{Capsule, ChainSegment, Circle, Polygon, Segment, Shape};

/// One contact point.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ManifoldPoint {
    /// The point (midway between the surfaces) relative to body A's centre of mass, in
    /// world orientation. Its world position is A's centre plus this (kept implicit: a
    /// contact is 192 bytes, three cache lines, which every contact stage streams).
    pub anchor_a: Vec2,
    /// The point relative to body B's centre of mass, in world orientation.
    pub anchor_b: Vec2,
    /// Signed distance between the surfaces along the normal (negative when overlapping).
    pub separation: f32,
    /// The separation when the manifold was last computed; a recycled contact refreshes
    /// `separation` from it and the bodies' motion since.
    pub base_separation: f32,
    /// Accumulated normal impulse (warm start for the next step).
    pub normal_impulse: f32,
    /// Accumulated friction impulse.
    pub tangent_impulse: f32,
    /// Largest normal impulse applied during the step (zero for a speculative point that
    /// never pushed).
    pub total_normal_impulse: f32,
    /// Normal relative velocity before the solve (for restitution).
    pub normal_velocity: f32,
    /// Feature id: `reference << 8 | incident`.
    pub id: u16,
    /// Whether the point matched a point of the previous step by id.
    pub persisted: bool,
}

/// Up to two contact points sharing one normal.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Manifold {
    /// Unit normal from A to B, in the world.
    pub normal: Vec2,
    /// The points; only the first `count` are used.
    pub points: [ManifoldPoint; 2],
    /// 0, 1 or 2.
    pub count: usize,
}

impl Manifold {
    /// The used points.
    pub fn points(&self) -> &[ManifoldPoint] {
        &self.points[..self.count]
    }
}

#[inline]
fn make_id(a: usize, b: usize) -> u16 {
    ((a as u16 & 0xff) << 8) | (b as u16 & 0xff)
}

/// Computes the manifold between two shapes at their transforms, the normal from A to B.
/// The world makes A the shape later in the order of shape types ([`Shape::rank`]); any
/// other order is served by swapping and flipping. Two segments (or chain segments) give no
/// points.
pub fn collide(
    shape_a: &Shape,
    xf_a: Transform,
    shape_b: &Shape,
    xf_b: Transform,
    max_distance: f32,
) -> Manifold {
    use Shape as S;
    let d = max_distance;
    match (shape_a, shape_b) {
        (S::Circle(a), S::Circle(b)) => collide_circles(a, xf_a, b, xf_b, d),
        (S::Capsule(a), S::Circle(b)) => {
            collide_capsule_circle(a.center1, a.center2, a.radius, xf_a, b, xf_b, d)
        }
        (S::Capsule(a), S::Capsule(b)) => collide_capsules(
            (a.center1, a.center2, a.radius),
            xf_a,
            (b.center1, b.center2, b.radius),
            xf_b,
            d,
        ),
        (S::Polygon(a), S::Circle(b)) => collide_polygon_circle(a, xf_a, b, xf_b, d),
        (S::Polygon(a), S::Capsule(b)) => collide_polygons(a, xf_a, &capsule_polygon(b), xf_b, d),
        (S::Polygon(a), S::Polygon(b)) => collide_polygons(a, xf_a, b, xf_b, d),
        (S::Segment(a), S::Circle(b)) => {
            collide_capsule_circle(a.point1, a.point2, 0.0, xf_a, b, xf_b, d)
        }
        (S::Segment(a), S::Capsule(b)) => collide_capsules(
            (a.point1, a.point2, 0.0),
            xf_a,
            (b.center1, b.center2, b.radius),
            xf_b,
            d,
        ),
        (S::Segment(a), S::Polygon(b)) => collide_polygons(&segment_polygon(a), xf_a, b, xf_b, d),
        (S::ChainSegment(a), S::Circle(b)) => collide_chain_segment_circle(a, xf_a, b, xf_b, d),
        (S::ChainSegment(a), S::Capsule(b)) => {
            collide_chain_segment_polygon(a, xf_a, &capsule_polygon(b), xf_b, d)
        }
        (S::ChainSegment(a), S::Polygon(b)) => collide_chain_segment_polygon(a, xf_a, b, xf_b, d),
        (S::Segment(_) | S::ChainSegment(_), S::Segment(_) | S::ChainSegment(_)) => {
            Manifold::default()
        }
        _ => {
            // A before B in the order: not produced by the world; kept total by flipping.
            let mut m = collide(shape_b, xf_b, shape_a, xf_a, max_distance);
            flip(&mut m);
            m
        }
    }
}

fn capsule_polygon(c: &Capsule) -> Polygon {
    Polygon::capsule(c.center1, c.center2, c.radius)
}

fn segment_polygon(s: &Segment) -> Polygon {
    Polygon::capsule(s.point1, s.point2, 0.0)
}

fn flip(m: &mut Manifold) {
    m.normal = -m.normal;
    for p in &mut m.points[..m.count] {
        std::mem::swap(&mut p.anchor_a, &mut p.anchor_b);
    }
}

/// Both anchors of a point given in A's local frame.
#[inline]
fn anchors(xf_a: Transform, xf_b: Transform, local: Vec2) -> (Vec2, Vec2) {
    let anchor_a = xf_a.q.apply(local);
    let anchor_b = anchor_a + (xf_a.p - xf_b.p);
    (anchor_a, anchor_b)
}

fn single(
    xf_a: Transform,
    xf_b: Transform,
    normal_local: Vec2,
    local: Vec2,
    sep: f32,
    id: u16,
) -> Manifold {
    local_manifold(xf_a, xf_b, normal_local, &[(local, sep, id)])
}

/// Circle against circle: one point on the line between the centres.
pub fn collide_circles(
    a: &Circle,
    xf_a: Transform,
    b: &Circle,
    xf_b: Transform,
    max_distance: f32,
) -> Manifold {
    // Work in A's frame so that far-from-origin scenes keep their precision.
    let c = xf_a.apply_inv(xf_b.p);
    let (mut normal, dist) = normalize_and_length(c);
    let sep = dist - a.radius - b.radius;
    if sep > max_distance {
        return Manifold::default();
    }
    if dist == 0.0 {
        // Concentric: any direction separates them; pick one that is the same every run.
        normal = Vec2::Y;
    }
    let ca = normal * a.radius;
    let cb = c - normal * b.radius;
    let mid = (ca + cb) * 0.5;
    single(xf_a, xf_b, normal, mid, sep, 0)
}

/// Capsule (or segment, radius 0) A against circle B: the closest point of A's core segment
/// to B's centre (Box2D's `b2CollideCapsuleAndCircle`).
#[allow(clippy::too_many_arguments)]
pub fn collide_capsule_circle(
    p1: Vec2,
    p2: Vec2,
    radius_a: f32,
    xf_a: Transform,
    b: &Circle,
    xf_b: Transform,
    max_distance: f32,
) -> Manifold {
    let c = xf_a.apply_inv(xf_b.p);
    let e = p2 - p1;
    let s1 = dot(c - p1, e);
    let s2 = dot(p2 - c, e);
    let closest = if s1 < 0.0 {
        p1
    } else if s2 < 0.0 {
        p2
    } else {
        p1 + e * (s1 / dot(e, e))
    };
    // A centre on the core: the core's left normal, the same every run.
    let on_core = Vec2::new(-e.y, e.x);
    point_against_circle(
        xf_a,
        xf_b,
        (closest, radius_a),
        (c, b.radius),
        on_core,
        max_distance,
    )
}

/// A's point `closest` grown by `radius_a` against a circle centred at `c` (both in A's
/// frame): one point midway between the surfaces, the normal from `closest` to `c`, or along
/// `fallback` when they coincide.
fn point_against_circle(
    xf_a: Transform,
    xf_b: Transform,
    (closest, radius_a): (Vec2, f32),
    (c, radius_b): (Vec2, f32),
    fallback: Vec2,
    max_distance: f32,
) -> Manifold {
    let (mut normal, dist) = normalize_and_length(c - closest);
    let sep = dist - radius_a - radius_b;
    if sep > max_distance {
        return Manifold::default();
    }
    if dist == 0.0 {
        normal = fallback.normalize_or(Vec2::Y);
    }
    let ca = closest + normal * radius_a;
    let cb = c - normal * radius_b;
    single(xf_a, xf_b, normal, (ca + cb) * 0.5, sep, 0)
}

/// Capsule A against capsule B, each a core segment `(p, q)` and a radius (a segment is a
/// capsule of radius 0): the closest points of the cores (Ericson, Real-Time Collision
/// Detection 5.1.9), and where each core projects onto the other, the incident core clipped
/// to the reference core's ends for two points, unless they would be much farther apart than
/// the closest points (Box2D v3's `b2CollideCapsules`). Collinear cores meet end to end along
/// their common line, which the polygon routine's side normals cannot express.
pub fn collide_capsules(
    (a1, a2, radius_a): (Vec2, Vec2, f32),
    xf_a: Transform,
    (b1, b2, radius_b): (Vec2, Vec2, f32),
    xf_b: Transform,
    max_distance: f32,
) -> Manifold {
    // In A's frame, shifted to A's first centre for round-off.
    let origin = a1;
    let xf = xf_a.inv_mul(xf_b);
    let p1 = Vec2::ZERO;
    let q1 = a2 - origin;
    let p2 = xf.apply(b1) - origin;
    let q2 = xf.apply(b2) - origin;
    let sd = segment_distance(p1, q1, p2, q2);
    let radius = radius_a + radius_b;
    let reach = radius + max_distance;
    if sd.distance_squared > reach * reach {
        return Manifold::default();
    }
    let distance = sd.distance_squared.sqrt();
    let (d1, d2) = (q1 - p1, q2 - p2);
    let (u1, length1) = normalize_and_length(d1);
    let (u2, length2) = normalize_and_length(d2);
    // Where each core's ends project onto the other core's line.
    let (fp2, fq2) = (dot(p2 - p1, u1), dot(q2 - p1, u1));
    let outside_a = (fp2 <= 0.0 && fq2 <= 0.0) || (fp2 >= length1 && fq2 >= length1);
    let (fp1, fq1) = (dot(p1 - p2, u2), dot(q1 - p2, u2));
    let outside_b = (fp1 <= 0.0 && fq1 <= 0.0) || (fp1 >= length2 && fq1 >= length2);
    let mut points: [(Vec2, f32, u16); 2] = [(Vec2::ZERO, 0.0, 0); 2];
    let mut count = 0;
    let mut normal = Vec2::ZERO;
    if !outside_a && !outside_b {
        // Side by side: each core's side facing the other, and how far the other core lies
        // beyond it (the separating axis of the two lines).
        let side = |u: Vec2, base: Vec2, a: Vec2, b: Vec2| {
            let n = Vec2::new(-u.y, u.x);
            let (s1, s2) = (dot(a - base, n), dot(b - base, n));
            let (plus, minus) = (s1.min(s2), (-s1).min(-s2));
            if plus > minus { (n, plus) } else { (-n, minus) }
        };
        let (normal_a, separation_a) = side(u1, p1, p2, q2);
        let (normal_b, separation_b) = side(u2, p2, p1, q1);
        // Biased towards A's side, so the reference does not flip from step to step.
        let clip = |from: (Vec2, Vec2), f: (f32, f32), length: f32| {
            let ((mut cp, mut cq), (fp, fq)) = (from, f);
            let (p, q) = from;
            if fp < 0.0 && fq > 0.0 {
                cp = p.lerp(q, (0.0 - fp) / (fq - fp));
            } else if fq < 0.0 && fp > 0.0 {
                cq = q.lerp(p, (0.0 - fq) / (fp - fq));
            }
            if fp > length && fq < length {
                cp = p.lerp(q, (fp - length) / (fp - fq));
            } else if fq > length && fp < length {
                cq = q.lerp(p, (fq - length) / (fq - fp));
            }
            (cp, cq)
        };
        if separation_a + 0.1 * LINEAR_SLOP >= separation_b {
            let (cp, cq) = clip((p2, q2), (fp2, fq2), length1);
            let (sp, sq) = (dot(cp - p1, normal_a), dot(cq - p1, normal_a));
            if sp <= distance + LINEAR_SLOP || sq <= distance + LINEAR_SLOP {
                normal = normal_a;
                let mid = |c: Vec2, s: f32| c + normal_a * (0.5 * (radius_a - radius_b - s));
                points = [
                    (mid(cp, sp), sp - radius, make_id(0, 0)),
                    (mid(cq, sq), sq - radius, make_id(0, 1)),
                ];
                count = 2;
            }
        } else {
            let (cp, cq) = clip((p1, q1), (fp1, fq1), length2);
            let (sp, sq) = (dot(cp - p2, normal_b), dot(cq - p2, normal_b));
            if sp <= distance + LINEAR_SLOP || sq <= distance + LINEAR_SLOP {
                // B is the reference; the normal still runs from A to B.
                normal = -normal_b;
                let mid = |c: Vec2, s: f32| c + normal_b * (0.5 * (radius_b - radius_a - s));
                points = [
                    (mid(cp, sp), sp - radius, make_id(0, 0)),
                    (mid(cq, sq), sq - radius, make_id(1, 0)),
                ];
                count = 2;
            }
        }
    }
    if count == 0 {
        // One point between the closest points of the cores.
        let c1 = p1 + d1 * sd.fraction1;
        let c2 = p2 + d2 * sd.fraction2;
        normal = if sd.distance_squared > f32::EPSILON * f32::EPSILON {
            (c2 - c1) * (1.0 / distance)
        } else {
            Vec2::new(-u1.y, u1.x)
        };
        let ca = c1 + normal * radius_a;
        let cb = c2 - normal * radius_b;
        let (i1, i2) = (
            usize::from(sd.fraction1 != 0.0),
            usize::from(sd.fraction2 != 0.0),
        );
        points[0] = ((ca + cb) * 0.5, distance - radius, make_id(i1, i2));
        count = 1;
    }
    for p in &mut points[..count] {
        p.0 += origin;
    }
    local_manifold(xf_a, xf_b, normal, &points[..count])
}

/// Polygon (A, maybe rounded) against circle (B): face contact or one of the two vertex
/// regions (Box2D's `b2CollidePolygonAndCircle`).
pub fn collide_polygon_circle(
    a: &Polygon,
    xf_a: Transform,
    b: &Circle,
    xf_b: Transform,
    max_distance: f32,
) -> Manifold {
    let c = xf_a.apply_inv(xf_b.p);
    let radius_a = a.radius;
    let radius = radius_a + b.radius;
    let n = a.count;
    let mut best = 0;
    let mut separation = f32::MIN;
    for i in 0..n {
        let s = dot(a.normals[i], c - a.vertices[i]);
        if s > separation {
            separation = s;
            best = i;
        }
    }
    if separation - radius > max_distance {
        return Manifold::default();
    }
    let v1 = a.vertices[best];
    let v2 = a.vertices[(best + 1) % n];
    let u1 = dot(c - v1, v2 - v1);
    let u2 = dot(c - v2, v1 - v2);
    let vertex = if u1 < 0.0 && separation > f32::EPSILON {
        Some(v1)
    } else if u2 < 0.0 && separation > f32::EPSILON {
        Some(v2)
    } else {
        None
    };
    match vertex {
        Some(v) => {
            // Vertex region: the normal runs from the vertex to the centre.
            let (normal, dist) = normalize_and_length(c - v);
            let sep = dist - radius;
            if sep > max_distance {
                return Manifold::default();
            }
            let ca = v + normal * radius_a;
            let cb = c - normal * b.radius;
            single(xf_a, xf_b, normal, (ca + cb) * 0.5, sep, 0)
        }
        None => {
            let normal = a.normals[best];
            let ca = c - normal * (dot(c - v1, normal) - radius_a);
            let cb = c - normal * b.radius;
            single(xf_a, xf_b, normal, (ca + cb) * 0.5, dot(cb - ca, normal), 0)
        }
    }
}

/// For each edge normal of `p1`, the deepest vertex of `p2` below it; returns the edge with
/// the largest such separation (the separating-axis test, Box2D's `b2FindMaxSeparation`).
fn find_max_separation(v1: &[Vec2], n1: &[Vec2], p2v: &[Vec2]) -> (usize, f32) {
    let mut best = 0;
    let mut max_sep = f32::MIN;
    for i in 0..v1.len() {
        let n = n1[i];
        let v = v1[i];
        let mut si = f32::MAX;
        for w in p2v {
            // A plain comparison, not `f32::min`: the points are finite, and `min`'s NaN
            // rule cost three more instructions in this, the narrow phase's inner loop.
            let d = dot(n, *w - v);
            if d < si {
                si = d;
            }
        }
        if si > max_sep {
            max_sep = si;
            best = i;
        }
    }
    (best, max_sep)
}

struct SegmentDistance {
    fraction1: f32,
    fraction2: f32,
    distance_squared: f32,
}

/// Closest points of segments p1–q1 and p2–q2 (Ericson, Real-Time Collision Detection 5.1.9).
fn segment_distance(p1: Vec2, q1: Vec2, p2: Vec2, q2: Vec2) -> SegmentDistance {
    let d1 = q1 - p1;
    let d2 = q2 - p2;
    let r = p1 - p2;
    let dd1 = dot(d1, d1);
    let dd2 = dot(d2, d2);
    let rd1 = dot(r, d1);
    let rd2 = dot(r, d2);
    let eps_sqr = f32::EPSILON * f32::EPSILON;
    let (f1, f2);
    if dd1 < eps_sqr || dd2 < eps_sqr {
        if dd1 >= eps_sqr {
            f1 = (-rd1 / dd1).clamp(0.0, 1.0);
            f2 = 0.0;
        } else if dd2 >= eps_sqr {
            f1 = 0.0;
            f2 = (rd2 / dd2).clamp(0.0, 1.0);
        } else {
            f1 = 0.0;
            f2 = 0.0;
        }
    } else {
        let d12 = dot(d1, d2);
        let denom = dd1 * dd2 - d12 * d12;
        // Parallel segments: start from the first segment's start.
        let mut a = if denom != 0.0 {
            ((d12 * rd2 - rd1 * dd2) / denom).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let mut b = (d12 * a + rd2) / dd2;
        if b < 0.0 {
            b = 0.0;
            a = (-rd1 / dd1).clamp(0.0, 1.0);
        } else if b > 1.0 {
            b = 1.0;
            a = ((d12 - rd1) / dd1).clamp(0.0, 1.0);
        }
        f1 = a;
        f2 = b;
    }
    let c1 = p1 + d1 * f1;
    let c2 = p2 + d2 * f2;
    SegmentDistance {
        fraction1: f1,
        fraction2: f2,
        distance_squared: (c1 - c2).length_squared(),
    }
}

/// Polygon against polygon, either maybe rounded or a two-vertex capsule or segment: SAT of
/// the cores both ways, then clip the incident edge against the reference face, the points
/// moved out by the radii (Box2D v3's `b2CollidePolygons` and `b2ClipPolygons`).
pub fn collide_polygons(
    a: &Polygon,
    xf_a: Transform,
    b: &Polygon,
    xf_b: Transform,
    max_distance: f32,
) -> Manifold {
    // Shift the origin to A's first vertex to limit round-off far from the body centre.
    let origin = a.vertices[0];
    let xf = xf_a.inv_mul(xf_b);
    let na = a.count;
    let nb = b.count;
    let mut va = [Vec2::ZERO; 8];
    let mut vb = [Vec2::ZERO; 8];
    let mut nbv = [Vec2::ZERO; 8];
    for i in 0..na {
        va[i] = a.vertices[i] - origin;
    }
    for i in 0..nb {
        vb[i] = xf.apply(b.vertices[i]) - origin;
    }
    let (va, vb) = (&va[..na], &vb[..nb]);
    let an = &a.normals[..na];
    let radius = a.radius + b.radius;
    let (mut edge_a, sep_a) = find_max_separation(va, an, vb);
    // Apart by more than the margin along one of A's normals: no manifold, whatever B's
    // normals say (the same result as testing both, as Box2D does; a long turning wall's
    // pairs with the bodies its box spans are mostly this).
    if sep_a - radius > max_distance {
        return Manifold::default();
    }
    for i in 0..nb {
        nbv[i] = xf.q.apply(b.normals[i]);
    }
    let bn = &nbv[..nb];
    let (mut edge_b, sep_b) = find_max_separation(vb, bn, va);
    if sep_b - radius > max_distance {
        return Manifold::default();
    }
    // The reference face is the one of greater separation; the incident edge is the other
    // polygon's edge most anti-parallel to it (Box2D v3 `b2CollidePolygons`).
    let flip = sep_b > sep_a;
    let most_anti_parallel = |search: Vec2, normals: &[Vec2]| {
        let mut best = 0;
        let mut min_dot = f32::MAX;
        for (i, n) in normals.iter().enumerate() {
            let d = dot(search, *n);
            if d < min_dot {
                min_dot = d;
                best = i;
            }
        }
        best
    };
    if flip {
        edge_a = most_anti_parallel(bn[edge_b], an);
    } else {
        edge_b = most_anti_parallel(an[edge_a], bn);
    }
    let radii = (a.radius, b.radius);
    let clipped = || {
        clip(
            xf_a, xf_b, origin, va, an, vb, bn, radii, edge_a, edge_b, flip,
        )
    };
    if sep_a.max(sep_b) <= 0.1 * LINEAR_SLOP {
        // Overlapping (or all but touching): clip.
        return clipped();
    }
    // Separated: the closest points of A's edge and B's edge. Where they are two vertices
    // and clearly farther apart than the clipped points claim, one point along the line
    // between the vertices gives the right speculative normal round corners.
    let i11 = edge_a;
    let i12 = (edge_a + 1) % na;
    let i21 = edge_b;
    let i22 = (edge_b + 1) % nb;
    let (v11, v12, v21, v22) = (va[i11], va[i12], vb[i21], vb[i22]);
    let sd = segment_distance(v11, v12, v21, v22);
    let distance = sd.distance_squared.sqrt();
    if distance - radius > max_distance {
        return Manifold::default();
    }
    let m = clipped();
    let min_separation = m.points().iter().fold(f32::MAX, |s, p| s.min(p.separation));
    if distance - radius + 0.1 * LINEAR_SLOP >= min_separation {
        return m;
    }
    let corner = |f: f32, first: (Vec2, usize), second: (Vec2, usize)| {
        if f == 0.0 {
            Some(first)
        } else if f == 1.0 {
            Some(second)
        } else {
            None
        }
    };
    match (
        corner(sd.fraction1, (v11, i11), (v12, i12)),
        corner(sd.fraction2, (v21, i21), (v22, i22)),
    ) {
        (Some((p1, k1)), Some((p2, k2))) if distance > 0.0 => {
            let n = (p2 - p1) * (1.0 / distance);
            // Midway between the two rounded surfaces.
            let mid = p1 + n * (0.5 * (distance + a.radius - b.radius));
            single(
                xf_a,
                xf_b,
                n,
                mid + origin,
                distance - radius,
                make_id(k1, k2),
            )
        }
        _ => m,
    }
}

/// Clips the incident edge to the side planes of the reference edge and keeps both points,
/// however far one is: the solver's speculative branch handles it (Box2D `b2ClipPolygons`).
/// Vertices and normals are in A's frame, shifted by `origin`.
fn clip(
    xf_a: Transform,
    xf_b: Transform,
    origin: Vec2,
    va: &[Vec2],
    an: &[Vec2],
    vb: &[Vec2],
    bn: &[Vec2],
    (radius_a, radius_b): (f32, f32),
    edge_a: usize,
    edge_b: usize,
    flip: bool,
) -> Manifold {
    let ((v1s, n1s, e1, r1), (v2s, e2, r2)) = if flip {
        ((vb, bn, edge_b, radius_b), (va, edge_a, radius_a))
    } else {
        ((va, an, edge_a, radius_a), (vb, edge_b, radius_b))
    };
    let i11 = e1;
    let i12 = (e1 + 1) % v1s.len();
    let i21 = e2;
    let i22 = (e2 + 1) % v2s.len();
    let normal = n1s[i11];
    let (v11, v12, v21, v22) = (v1s[i11], v1s[i12], v2s[i21], v2s[i22]);
    let ids = if flip {
        (make_id(i22, i11), make_id(i21, i12))
    } else {
        (make_id(i11, i22), make_id(i12, i21))
    };
    let Some([lower, upper]) = clip_segments((v11, v12), (v21, v22), normal, r1, r2, ids) else {
        return Manifold::default();
    };
    let shifted = |(p, sep, id): (Vec2, f32, u16)| (p + origin, sep, id);
    // With B as the reference the normal is turned to run from A to B, and the points are
    // listed from B's edge start, as the unflipped pair lists them from A's.
    if flip {
        local_manifold(xf_a, xf_b, -normal, &[shifted(upper), shifted(lower)])
    } else {
        local_manifold(xf_a, xf_b, normal, &[shifted(lower), shifted(upper)])
    }
}

/// Chain segment A against circle B: one-sided, and a centre in the region of a neighbour's
/// vertex is left to that neighbour, so a ball rolling across a joint meets one segment at a
/// time (Box2D's `b2CollideChainSegmentAndCircle`).
pub fn collide_chain_segment_circle(
    a: &ChainSegment,
    xf_a: Transform,
    b: &Circle,
    xf_b: Transform,
    max_distance: f32,
) -> Manifold {
    let c = xf_a.apply_inv(xf_b.p);
    let (p1, p2) = (a.segment.point1, a.segment.point2);
    let e = p2 - p1;
    // The pushing side is the right-hand one.
    if dot(right_perp(e), c - p1) < 0.0 {
        return Manifold::default();
    }
    let u = dot(e, p2 - c);
    let v = dot(e, c - p1);
    let closest = if v <= 0.0 {
        // Behind point1: the previous segment's if the centre is in its region.
        if dot(p1 - a.ghost1, c - p1) <= 0.0 {
            return Manifold::default();
        }
        p1
    } else if u <= 0.0 {
        // Ahead of point2: the next segment's if the centre is in its region.
        if dot(a.ghost2 - p2, c - p2) > 0.0 {
            return Manifold::default();
        }
        p2
    } else {
        p1 + e * (v / dot(e, e))
    };
    // A centre on the segment: its pushing side.
    let fallback = right_perp(e);
    point_against_circle(
        xf_a,
        xf_b,
        (closest, 0.0),
        (c, b.radius),
        fallback,
        max_distance,
    )
}

/// The closest features of a segment and a convex polygon's core (two or more vertices, in
/// the same frame): what a distance query (GJK) would report, found here by testing the
/// segment against each of the polygon's at most 8 edges.
#[derive(Clone, Copy, Debug, PartialEq)]
struct SegmentPolygonDistance {
    distance: f32,
    /// The closest point on the segment.
    point_a: Vec2,
    /// The closest point on the polygon.
    point_b: Vec2,
    /// The segment's vertex (0 or 1) that is closest, or `None` for its interior.
    vertex_a: Option<usize>,
    /// The polygon's closest edge, and its vertex (0 for the edge's start, 1 for its end)
    /// that is closest, or `None` for the edge's interior.
    edge_b: usize,
    vertex_b: Option<usize>,
}

fn segment_polygon_distance(p1: Vec2, p2: Vec2, vertices: &[Vec2]) -> SegmentPolygonDistance {
    let n = vertices.len();
    let mut best: Option<(SegmentDistance, usize)> = None;
    for j in 0..n {
        let sd = segment_distance(p1, p2, vertices[j], vertices[(j + 1) % n]);
        if best
            .as_ref()
            .is_none_or(|(b, _)| sd.distance_squared < b.distance_squared)
        {
            best = Some((sd, j));
        }
    }
    let (sd, j) = best.expect("a polygon has edges");
    let (w1, w2) = (vertices[j], vertices[(j + 1) % n]);
    let end = |f: f32| {
        if f == 0.0 {
            Some(0)
        } else if f == 1.0 {
            Some(1)
        } else {
            None
        }
    };
    // A segment end inside a polygon of area is no distance from it.
    let inside = |p: Vec2| {
        n >= 3
            && (0..n).all(|k| {
                let e = vertices[(k + 1) % n] - vertices[k];
                crate::math::cross(e, p - vertices[k]) >= 0.0
            })
    };
    let distance = if inside(p1) || inside(p2) {
        0.0
    } else {
        sd.distance_squared.sqrt()
    };
    SegmentPolygonDistance {
        distance,
        point_a: p1 + (p2 - p1) * sd.fraction1,
        point_b: w1 + (w2 - w1) * sd.fraction2,
        vertex_a: end(sd.fraction1),
        edge_b: j,
        vertex_b: end(sd.fraction2),
    }
}

/// Clips incident segment `b1`–`b2` (running against the tangent) to reference segment
/// `a1`–`a2` whose `normal` points towards it; the points lie midway between the surfaces
/// moved out by the radii `ra` and `rb` (Box2D's `b2ClipSegments`). In A's frame.
#[allow(clippy::too_many_arguments)]
fn clip_segments(
    (a1, a2): (Vec2, Vec2),
    (b1, b2): (Vec2, Vec2),
    normal: Vec2,
    ra: f32,
    rb: f32,
    ids: (u16, u16),
) -> Option<[(Vec2, f32, u16); 2]> {
    let tangent = Vec2::new(-normal.y, normal.x);
    let lower1 = 0.0;
    let upper1 = dot(a2 - a1, tangent);
    let upper2 = dot(b1 - a1, tangent);
    let lower2 = dot(b2 - a1, tangent);
    if upper2 < lower1 || upper1 < lower2 {
        return None;
    }
    let span = upper2 - lower2;
    let v_lower = if lower2 < lower1 && span > f32::EPSILON {
        b2.lerp(b1, (lower1 - lower2) / span)
    } else {
        b2
    };
    let v_upper = if upper2 > upper1 && span > f32::EPSILON {
        b2.lerp(b1, (upper1 - lower2) / span)
    } else {
        b1
    };
    let sep_lower = dot(v_lower - a1, normal);
    let sep_upper = dot(v_upper - a1, normal);
    let radius = ra + rb;
    Some([
        (
            v_lower + normal * (0.5 * (ra - rb - sep_lower)),
            sep_lower - radius,
            ids.0,
        ),
        (
            v_upper + normal * (0.5 * (ra - rb - sep_upper)),
            sep_upper - radius,
            ids.1,
        ),
    ])
}

/// A manifold of points given in A's frame.
fn local_manifold(
    xf_a: Transform,
    xf_b: Transform,
    normal_local: Vec2,
    points: &[(Vec2, f32, u16)],
) -> Manifold {
    let mut m = Manifold {
        normal: xf_a.q.apply(normal_local),
        count: points.len(),
        ..Manifold::default()
    };
    for (k, &(local, separation, id)) in points.iter().enumerate() {
        let (anchor_a, anchor_b) = anchors(xf_a, xf_b, local);
        m.points[k] = ManifoldPoint {
            anchor_a,
            anchor_b,
            separation,
            id,
            ..ManifoldPoint::default()
        };
    }
    m
}

/// How a candidate normal (from the chain segment towards B) relates to the chain's
/// neighbouring segments, by where it falls on the Gauss map of the joints (Box2D's
/// `b2ClassifyNormal`; box2d.org/posts/2020/06/ghost-collisions).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum NormalType {
    /// Past a convex joint into the neighbour's range: the neighbour owns this contact.
    Skip,
    /// Within the segment's own range: use it.
    Admit,
    /// At a concave joint: use the segment's own normal instead.
    Snap,
}

struct ChainJoints {
    edge1: Vec2,
    normal0: Vec2,
    normal2: Vec2,
    convex1: bool,
    convex2: bool,
}

impl ChainJoints {
    fn classify(&self, normal: Vec2) -> NormalType {
        use crate::math::cross;
        // sin of about half a degree: normals this close to a neighbour's count as its.
        const SIN_TOL: f32 = 0.01;
        let (convex, past) = if dot(normal, self.edge1) <= 0.0 {
            (self.convex1, cross(normal, self.normal0) > SIN_TOL)
        } else {
            (self.convex2, cross(self.normal2, normal) > SIN_TOL)
        };
        match (convex, past) {
            (false, _) => NormalType::Snap,
            (true, true) => NormalType::Skip,
            (true, false) => NormalType::Admit,
        }
    }
}

/// Chain segment A against polygon B (maybe rounded, or a capsule as a two-vertex polygon):
/// one-sided, and a normal that belongs to a neighbouring segment is left to it, so a box
/// sliding across the joint between two segments does not catch on it (Box2D's
/// `b2CollideChainSegmentAndPolygon`, with the closest features found by
/// `segment_polygon_distance` instead of GJK).
pub fn collide_chain_segment_polygon(
    a: &ChainSegment,
    xf_a: Transform,
    b: &Polygon,
    xf_b: Transform,
    max_distance: f32,
) -> Manifold {
    use crate::math::cross;
    let xf = xf_a.inv_mul(xf_b);
    let count = b.count;
    let mut vertices = [Vec2::ZERO; 8];
    let mut normals = [Vec2::ZERO; 8];
    for i in 0..count {
        vertices[i] = xf.apply(b.vertices[i]);
        normals[i] = xf.q.apply(b.normals[i]);
    }
    // Every shape with area is centred on its frame's origin (a capsule's core too).
    let centroid = xf.p;
    let (vertices, normals) = (&vertices[..count], &normals[..count]);
    let radius_b = b.radius;
    let (p1, p2) = (a.segment.point1, a.segment.point2);
    let edge1 = normalize_and_length(p2 - p1).0;
    // A joint is convex when the chain turns left there: less than 0.01 is straight.
    const CONVEX_TOL: f32 = 0.01;
    let edge0 = normalize_and_length(p1 - a.ghost1).0;
    let edge2 = normalize_and_length(a.ghost2 - p2).0;
    let joints = ChainJoints {
        edge1,
        normal0: right_perp(edge0),
        normal2: right_perp(edge2),
        convex1: cross(edge0, edge1) >= CONVEX_TOL,
        convex2: cross(edge1, edge2) >= CONVEX_TOL,
    };
    let normal1 = right_perp(edge1);
    let behind1 = dot(normal1, centroid - p1) < 0.0;
    let behind0 = !joints.convex1 || dot(joints.normal0, centroid - p1) < 0.0;
    let behind2 = !joints.convex2 || dot(joints.normal2, centroid - p2) < 0.0;
    if behind1 && behind0 && behind2 {
        // One-sided: B is behind this segment and its convex neighbours.
        return Manifold::default();
    }
    let closest = segment_polygon_distance(p1, p2, vertices);
    if closest.distance > radius_b + max_distance {
        return Manifold::default();
    }
    // At a concave joint the neighbour's normal is replaced by this segment's.
    let n0 = if joints.convex1 {
        joints.normal0
    } else {
        normal1
    };
    let n2 = if joints.convex2 {
        joints.normal2
    } else {
        normal1
    };
    let next = |i: usize| if i + 1 < count { i + 1 } else { 0 };
    // Whether the neighbour on the side of the segment's deeper end is the one B's face
    // `n` meets first (then it owns the contact).
    let neighbour_incident = |n: Vec2, a1: Vec2| {
        let (d1, d2) = (dot(n, p1 - a1), dot(n, p2 - a1));
        let neighbour = if d1 < d2 { n0 } else { n2 };
        dot(neighbour, n) < dot(normal1, n)
    };
    // B's face `reference` against the segment: B is the reference, the normal flipped to
    // run from A to B.
    let polygon_face = |reference: usize| {
        let (ia1, ia2) = (reference, next(reference));
        let n = normals[ia1];
        if neighbour_incident(n, vertices[ia1]) {
            return Manifold::default();
        }
        match clip_segments(
            (vertices[ia1], vertices[ia2]),
            (p1, p2),
            n,
            radius_b,
            0.0,
            (make_id(ia1, 1), make_id(ia2, 0)),
        ) {
            Some(points) => local_manifold(xf_a, xf_b, -n, &points),
            None => Manifold::default(),
        }
    };
    // The polygon edge that meets the segment's face: given directly, or the one of the
    // incident vertex's two edges most against the segment's normal.
    enum Incident {
        Edge(usize),
        Vertex(usize),
    }
    let incident;
    if !behind1 && closest.distance > 0.1 * LINEAR_SLOP {
        match (closest.vertex_a, closest.vertex_b) {
            (Some(ia), Some(jb)) => {
                // Vertex against vertex.
                let ib = if jb == 0 {
                    closest.edge_b
                } else {
                    next(closest.edge_b)
                };
                let normal = normalize_and_length(closest.point_b - closest.point_a).0;
                match joints.classify(normal) {
                    NormalType::Skip => return Manifold::default(),
                    NormalType::Admit => {
                        let cb = closest.point_b - normal * radius_b;
                        let point = (closest.point_a + cb) * 0.5;
                        let sep = closest.distance - radius_b;
                        return local_manifold(
                            xf_a,
                            xf_b,
                            normal,
                            &[(point, sep, make_id(ia, ib))],
                        );
                    }
                    NormalType::Snap => incident = Incident::Vertex(ib),
                }
            }
            (Some(_), None) => {
                // A segment vertex against a polygon edge: of the edge's side normals, the
                // one facing the segment (a capsule's core has two, back to back).
                let (ib1, ib2) = (closest.edge_b, next(closest.edge_b));
                let towards = closest.point_a - closest.point_b;
                let ib = if dot(towards, normals[ib1]) > dot(towards, normals[ib2]) {
                    ib1
                } else {
                    ib2
                };
                let normal_b = normals[ib];
                match joints.classify(-normal_b) {
                    NormalType::Skip => return Manifold::default(),
                    NormalType::Admit => return polygon_face(ib),
                    NormalType::Snap => incident = Incident::Edge(ib),
                }
            }
            (None, vertex_b) => {
                // The segment's interior against a polygon vertex (or an edge parallel to
                // it): the deeper of the edge's two ends along the segment's normal.
                let (ib1, ib2) = (closest.edge_b, next(closest.edge_b));
                let ib = match vertex_b {
                    Some(0) => ib1,
                    Some(_) => ib2,
                    None => {
                        let d1 = dot(normal1, vertices[ib1] - p1);
                        let d2 = dot(normal1, vertices[ib2] - p2);
                        if d1 < d2 { ib1 } else { ib2 }
                    }
                };
                incident = Incident::Vertex(ib);
            }
        }
    } else {
        // Overlapping (or B's centre behind the segment): separating axes. The segment's
        // normal, and its convex neighbours' (which, if they separate more, own B).
        let mut edge_separation = f32::MAX;
        let mut incident_index = None;
        for (i, v) in vertices.iter().enumerate() {
            let s = dot(normal1, *v - p1);
            if s < edge_separation {
                edge_separation = s;
                incident_index = Some(i);
            }
        }
        for (convex, n, p) in [
            (joints.convex1, joints.normal0, p1),
            (joints.convex2, joints.normal2, p2),
        ] {
            if convex {
                let s = vertices.iter().fold(f32::MAX, |m, v| m.min(dot(n, *v - p)));
                if s > edge_separation {
                    edge_separation = s;
                    incident_index = None;
                }
            }
        }
        // B's face normals that this segment may own.
        let mut polygon_separation = f32::MIN;
        let mut reference = None;
        for i in 0..count {
            let n = normals[i];
            if joints.classify(-n) != NormalType::Admit {
                continue;
            }
            let v = vertices[i];
            let s = dot(n, p2 - v).min(dot(n, p1 - v));
            if s > polygon_separation {
                polygon_separation = s;
                reference = Some(i);
            }
        }
        if let Some(r) = reference
            && polygon_separation > edge_separation
        {
            return polygon_face(r);
        }
        match incident_index {
            // A neighbouring segment separates more: it owns B.
            None => return Manifold::default(),
            Some(i) => incident = Incident::Vertex(i),
        }
    }
    // The segment is the reference face; B's incident edge is the one next to the incident
    // vertex most against the segment's normal.
    let (ib1, ib2) = match incident {
        Incident::Edge(i) => (i, next(i)),
        Incident::Vertex(i2) => {
            let i1 = if i2 > 0 { i2 - 1 } else { count - 1 };
            if dot(normal1, normals[i1]) < dot(normal1, normals[i2]) {
                (i1, i2)
            } else {
                (i2, next(i2))
            }
        }
    };
    match clip_segments(
        (p1, p2),
        (vertices[ib1], vertices[ib2]),
        normal1,
        0.0,
        radius_b,
        (make_id(0, ib2), make_id(1, ib1)),
    ) {
        Some(points) => local_manifold(xf_a, xf_b, normal1, &points),
        None => Manifold::default(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Rot;

    fn xf(x: f32, y: f32, angle: f32) -> Transform {
        Transform {
            p: Vec2::new(x, y),
            q: Rot::from_angle(angle),
        }
    }
    const MAX: f32 = crate::SPECULATIVE_DISTANCE;

    #[test]
    fn circles_overlapping() {
        let a = Circle { radius: 0.5 };
        let b = Circle { radius: 0.25 };
        let m = collide_circles(&a, xf(0.0, 0.0, 0.0), &b, xf(0.7, 0.0, 0.0), MAX);
        assert_eq!(m.count, 1);
        // Exact in f32: 0.7 - 0.75.
        assert!((m.normal - Vec2::X).length() < 1e-6);
        assert!((m.points[0].separation - (-0.05)).abs() < 1e-6);
        // Midway between the surface points x=0.5 and x=0.45 (A at the origin: its anchor
        // is the world point).
        assert!((m.points[0].anchor_a - Vec2::new(0.475, 0.0)).length() < 1e-6);
        assert!((m.points[0].anchor_b - Vec2::new(-0.225, 0.0)).length() < 1e-6);
        assert_eq!(m.points[0].id, 0);
    }

    #[test]
    fn circles_apart_beyond_margin() {
        let a = Circle { radius: 0.5 };
        let m = collide_circles(&a, xf(0.0, 0.0, 0.0), &a, xf(1.1, 0.0, 0.0), MAX);
        assert_eq!(m.count, 0);
        // Within the margin: a speculative point with positive separation.
        let m = collide_circles(&a, xf(0.0, 0.0, 0.0), &a, xf(1.01, 0.0, 0.0), MAX);
        assert_eq!(m.count, 1);
        assert!((m.points[0].separation - 0.01).abs() < 1e-6);
    }

    #[test]
    fn polygon_circle_face_and_vertex() {
        let b = Polygon::new_box(1.0, 0.5);
        let c = Circle { radius: 0.25 };
        // Resting on the top face, 0.05 deep.
        let m = collide_polygon_circle(&b, xf(0.0, 0.0, 0.0), &c, xf(0.3, 0.7, 0.0), MAX);
        assert_eq!(m.count, 1);
        assert!((m.normal - Vec2::Y).length() < 1e-6);
        assert!((m.points[0].separation + 0.05).abs() < 1e-6);
        assert!((m.points[0].anchor_a - Vec2::new(0.3, 0.475)).length() < 1e-6);
        // Off the top-right corner along the diagonal: vertex normal.
        let d = 0.2 / 2f32.sqrt();
        let m = collide_polygon_circle(&b, xf(0.0, 0.0, 0.0), &c, xf(1.0 + d, 0.5 + d, 0.0), MAX);
        assert_eq!(m.count, 1);
        let diag = Vec2::new(1.0, 1.0).normalize();
        assert!((m.normal - diag).length() < 1e-5);
        assert!((m.points[0].separation + 0.05).abs() < 1e-5);
    }

    #[test]
    fn box_resting_on_box_has_two_points_with_ids() {
        let ground = Polygon::new_box(5.0, 0.5);
        let bx = Polygon::new_box(0.5, 0.5);
        // Box centre at y = 0.99: 0.01 overlap.
        let m = collide_polygons(&ground, xf(0.0, 0.0, 0.0), &bx, xf(1.0, 0.99, 0.0), MAX);
        assert_eq!(m.count, 2);
        assert!((m.normal - Vec2::Y).length() < 1e-6);
        for p in m.points() {
            assert!((p.separation + 0.01).abs() < 1e-6, "{}", p.separation);
            // The ground at the origin: its anchor is the world point.
            assert!((p.anchor_a.y - 0.495).abs() < 1e-6);
        }
        // Clipping emits the incident edge's end vertex (x = 1.5) first.
        let xs = [m.points[0].anchor_a.x, m.points[1].anchor_a.x];
        assert!(
            (xs[0] - 1.5).abs() < 1e-6 && (xs[1] - 0.5).abs() < 1e-6,
            "{xs:?}"
        );
        // Reference edge 2 (ground top, vertices 2→3), incident edge 0 of the box.
        assert_eq!(m.points[0].id, make_id(2, 1));
        assert_eq!(m.points[1].id, make_id(3, 0));
        // Anchors denote the same world point from each body.
        for p in m.points() {
            assert!((p.anchor_b + Vec2::new(1.0, 0.99) - p.anchor_a).length() < 1e-6);
        }
    }

    #[test]
    fn flipped_reference_face_keeps_normal_from_a_to_b() {
        // Small box A sits on top of big box B: the normal from A to B is -y whichever face is
        // the reference.
        let small = Polygon::new_box(0.5, 0.5);
        let big = Polygon::new_box(5.0, 0.5);
        let m = collide_polygons(&small, xf(0.0, 0.99, 0.0), &big, xf(0.0, 0.0, 0.0), MAX);
        assert_eq!(m.count, 2);
        assert!((m.normal + Vec2::Y).length() < 1e-6);
        // The same two ids as the unflipped pair, with reference and incident swapped.
        let m2 = collide_polygons(&big, xf(0.0, 0.0, 0.0), &small, xf(0.0, 0.99, 0.0), MAX);
        let mut a: Vec<u16> = m.points().iter().map(|p| p.id).collect();
        let mut b: Vec<u16> = m2.points().iter().map(|p| p.id.rotate_left(8)).collect();
        a.sort();
        b.sort();
        assert_eq!(a, b);
    }

    #[test]
    fn rotated_box_corner_on_ground() {
        // A unit box turned 45° with its lowest corner 0.01 into the ground.
        let ground = Polygon::new_box(5.0, 0.5);
        let bx = Polygon::new_box(0.5, 0.5);
        let h = 0.5 * 2f32.sqrt();
        let m = collide_polygons(
            &ground,
            xf(0.0, 0.0, 0.0),
            &bx,
            xf(0.0, 0.5 + h - 0.01, std::f32::consts::FRAC_PI_4),
            MAX,
        );
        assert!((m.normal - Vec2::Y).length() < 1e-5);
        // One corner penetrates; the other end of the incident edge is far above, and is kept
        // all the same as a speculative point (Box2D emits both clipped points).
        assert_eq!(m.count, 2);
        let (deep, far) = (
            m.points[0].separation.min(m.points[1].separation),
            m.points[0].separation.max(m.points[1].separation),
        );
        assert!((deep + 0.01).abs() < 1e-5, "{deep}");
        // The side corner is h above the lowest one, less the 0.01 m overlap.
        assert!((far - (h - 0.01)).abs() < 1e-4, "{far}");
    }

    #[test]
    fn separated_corners_give_one_vertex_vertex_point() {
        // Two unit boxes corner to corner along the diagonal, 0.01 apart.
        let bx = Polygon::new_box(0.5, 0.5);
        let gap = 0.01 / 2f32.sqrt();
        let m = collide_polygons(
            &bx,
            xf(0.0, 0.0, 0.0),
            &bx,
            xf(1.0 + gap, 1.0 + gap, 0.0),
            MAX,
        );
        assert_eq!(m.count, 1);
        assert!((m.normal - Vec2::new(1.0, 1.0).normalize()).length() < 1e-4);
        assert!((m.points[0].separation - 0.01).abs() < 1e-5);
    }

    #[test]
    fn far_apart_polygons_have_no_points() {
        let bx = Polygon::new_box(0.5, 0.5);
        let m = collide_polygons(&bx, xf(0.0, 0.0, 0.0), &bx, xf(3.0, 0.0, 0.3), MAX);
        assert_eq!(m.count, 0);
    }

    fn capsule(x1: f32, y1: f32, x2: f32, y2: f32, r: f32) -> Shape {
        Shape::Capsule(Capsule {
            center1: Vec2::new(x1, y1),
            center2: Vec2::new(x2, y2),
            radius: r,
        })
    }

    /// A chain segment from `p1` to `p2` between ghosts `g1` and `g2`.
    fn chain(g1: [f32; 2], p1: [f32; 2], p2: [f32; 2], g2: [f32; 2]) -> Shape {
        Shape::ChainSegment(ChainSegment {
            ghost1: Vec2::from(g1),
            segment: Segment {
                point1: Vec2::from(p1),
                point2: Vec2::from(p2),
            },
            ghost2: Vec2::from(g2),
        })
    }

    fn at(x: f32, y: f32) -> Transform {
        xf(x, y, 0.0)
    }

    /// Sorted x of the points' world positions (A at the origin: `anchor_a`).
    fn xs(m: &Manifold) -> Vec<f32> {
        let mut v: Vec<f32> = m.points().iter().map(|p| p.anchor_a.x).collect();
        v.sort_by(f32::total_cmp);
        v
    }

    #[test]
    fn capsule_against_circle_side_and_end() {
        // Core (-1,0)-(1,0), radius 0.25; a circle of 0.5 above x = 0.3 at height 0.7: the
        // closest core point is (0.3, 0), so the separation is 0.7 - 0.75.
        let cap = capsule(-1.0, 0.0, 1.0, 0.0, 0.25);
        let ball = Shape::Circle(Circle { radius: 0.5 });
        let m = collide(&cap, at(0.0, 0.0), &ball, at(0.3, 0.7), MAX);
        assert_eq!(m.count, 1);
        assert!((m.normal - Vec2::Y).length() < 1e-6);
        assert!((m.points[0].separation + 0.05).abs() < 1e-6);
        // Midway between the capsule's surface (y = 0.25) and the circle's (y = 0.2).
        assert!((m.points[0].anchor_a - Vec2::new(0.3, 0.225)).length() < 1e-6);
        // Past the end (1, 0): the normal runs from the end centre to the circle's centre.
        let m = collide(&cap, at(0.0, 0.0), &ball, at(1.7, 0.0), MAX);
        assert!((m.normal - Vec2::X).length() < 1e-6);
        assert!((m.points[0].separation + 0.05).abs() < 1e-6);
    }

    #[test]
    fn segment_against_circle_is_a_capsule_of_radius_zero() {
        let seg = Shape::Segment(Segment {
            point1: Vec2::new(-1.0, 0.0),
            point2: Vec2::new(1.0, 0.0),
        });
        let ball = Shape::Circle(Circle { radius: 0.5 });
        // Two-sided: from below as from above.
        for y in [0.49f32, -0.49] {
            let m = collide(&seg, at(0.0, 0.0), &ball, at(0.2, y), MAX);
            assert_eq!(m.count, 1);
            assert!((m.normal - Vec2::new(0.0, y.signum())).length() < 1e-6);
            assert!((m.points[0].separation + 0.01).abs() < 1e-6);
            // Midway between the line and the circle's lowest point, 0.01 past it.
            assert!((m.points[0].anchor_a.y - y.signum() * -0.005).abs() < 1e-6);
        }
    }

    #[test]
    fn parallel_capsules_clip_to_two_points() {
        // Two capsules of core length 2 and radius 0.25, B 0.45 above A and 0.5 to the right:
        // the cores overlap on x in [-0.5, 1]; the separation is 0.45 - 0.5 at both ends of
        // the overlap, the points midway between the surfaces (y = 0.25 and y = 0.2).
        let cap = capsule(-1.0, 0.0, 1.0, 0.0, 0.25);
        let m = collide(&cap, at(0.0, 0.0), &cap, at(0.5, 0.45), MAX);
        assert_eq!(m.count, 2);
        assert!((m.normal - Vec2::Y).length() < 1e-6);
        for p in m.points() {
            assert!((p.separation + 0.05).abs() < 1e-6, "{}", p.separation);
            assert!((p.anchor_a.y - 0.225).abs() < 1e-6);
        }
        let x = xs(&m);
        assert!(
            (x[0] + 0.5).abs() < 1e-6 && (x[1] - 1.0).abs() < 1e-6,
            "{x:?}"
        );
        // Distinct feature ids, so each point keeps its impulse.
        assert_ne!(m.points[0].id, m.points[1].id);
    }

    #[test]
    fn collinear_capsules_meet_end_to_end() {
        // Cores (-1,0)-(1,0) and, 2.45 to the right, (1.45,0)-(3.45,0): the closest points are
        // the facing ends, 0.45 apart; one point, normal +x, separation 0.45 - 0.5, midway
        // between the end caps' surfaces x = 1.25 and x = 1.2.
        let cap = capsule(-1.0, 0.0, 1.0, 0.0, 0.25);
        let m = collide(&cap, at(0.0, 0.0), &cap, at(2.45, 0.0), MAX);
        assert_eq!(m.count, 1);
        assert!((m.normal - Vec2::X).length() < 1e-6, "{:?}", m.normal);
        assert!((m.points[0].separation + 0.05).abs() < 1e-6);
        assert!((m.points[0].anchor_a - Vec2::new(1.225, 0.0)).length() < 1e-6);
        // A's end 1, B's end 0.
        assert_eq!(m.points[0].id, make_id(1, 0));
    }

    #[test]
    fn capsule_on_a_segment_and_just_above_it() {
        // A capsule (core ±1, radius 0.25) lying on a segment along x: its core 0.24 up is
        // 0.01 deep at both ends; 0.26 up, two speculative points 0.01 apart from it.
        let seg = Shape::Segment(Segment {
            point1: Vec2::new(-5.0, 0.0),
            point2: Vec2::new(5.0, 0.0),
        });
        let cap = capsule(-1.0, 0.0, 1.0, 0.0, 0.25);
        for (height, separation) in [(0.24f32, -0.01f32), (0.26, 0.01)] {
            let m = collide(&seg, at(0.0, 0.0), &cap, at(0.5, height), MAX);
            assert_eq!(m.count, 2, "at {height}");
            assert!((m.normal - Vec2::Y).length() < 1e-6);
            for p in m.points() {
                assert!((p.separation - separation).abs() < 1e-5, "{}", p.separation);
                // Midway between the segment (y = 0) and the capsule's bottom.
                assert!((p.anchor_a.y - 0.5 * separation).abs() < 1e-5);
            }
            let x = xs(&m);
            assert!(
                (x[0] + 0.5).abs() < 1e-5 && (x[1] - 1.5).abs() < 1e-5,
                "{x:?}"
            );
        }
    }

    #[test]
    fn crossed_capsules_meet_at_one_point() {
        // B turned 90° and 0.45 above A's core: the cores' closest points are (0,0) and
        // (0,0.45), interior to both, so one point, normal +y, separation 0.45 - 0.5.
        let cap = capsule(-1.0, 0.0, 1.0, 0.0, 0.25);
        let m = collide(
            &cap,
            at(0.0, 0.0),
            &cap,
            xf(0.0, 1.45, std::f32::consts::FRAC_PI_2),
            MAX,
        );
        assert!(m.count >= 1);
        assert!((m.normal - Vec2::Y).length() < 1e-5, "{:?}", m.normal);
        let deepest = m.points().iter().fold(f32::MAX, |s, p| s.min(p.separation));
        // B's lower end centre is at y = 0.45: 0.45 - 0.25 - 0.25.
        assert!((deepest + 0.05).abs() < 1e-5, "{deepest}");
    }

    #[test]
    fn capsule_lying_on_a_box() {
        // Ground box of half height 0.5; a capsule's core 0.24 above its top, radius 0.25:
        // 0.01 deep at both ends of the core, points midway between y = 0.5 and y = 0.49.
        let ground = Shape::Polygon(Polygon::new_box(5.0, 0.5));
        let cap = capsule(-1.0, 0.0, 1.0, 0.0, 0.25);
        let m = collide(&ground, at(0.0, 0.0), &cap, at(0.0, 0.74), MAX);
        assert_eq!(m.count, 2);
        assert!((m.normal - Vec2::Y).length() < 1e-6);
        for p in m.points() {
            assert!((p.separation + 0.01).abs() < 1e-5, "{}", p.separation);
            assert!((p.anchor_a.y - 0.495).abs() < 1e-5);
        }
        let x = xs(&m);
        assert!(
            (x[0] + 1.0).abs() < 1e-5 && (x[1] - 1.0).abs() < 1e-5,
            "{x:?}"
        );
    }

    #[test]
    fn rounded_box_rests_on_its_rounded_surface() {
        // A unit box rounded by 0.1 whose core's bottom is 0.09 above the ground: 0.01 deep.
        let ground = Shape::Polygon(Polygon::new_box(5.0, 0.5));
        let mut core = Polygon::new_box(0.5, 0.5);
        core.radius = 0.1;
        let rounded = Shape::Polygon(core);
        let m = collide(&ground, at(0.0, 0.0), &rounded, at(0.0, 1.09), MAX);
        assert_eq!(m.count, 2);
        assert!((m.normal - Vec2::Y).length() < 1e-6);
        for p in m.points() {
            assert!((p.separation + 0.01).abs() < 1e-5, "{}", p.separation);
            // Midway between the ground (0.5) and the rounded bottom (0.49).
            assert!((p.anchor_a.y - 0.495).abs() < 1e-5);
        }
        // The core's width: the points sit under its bottom corners.
        let x = xs(&m);
        assert!(
            (x[0] + 0.5).abs() < 1e-5 && (x[1] - 0.5).abs() < 1e-5,
            "{x:?}"
        );
        // Off the rounded corner along the diagonal, a circle meets the corner's arc: the
        // core corner (0.5, 0.5) + 0.1 along (1,1)/√2, then a 0.01 gap to a circle of 0.2.
        let ball = Shape::Circle(Circle { radius: 0.2 });
        let d = (0.1 + 0.01 + 0.2) / 2f32.sqrt();
        let m = collide(&rounded, at(0.0, 0.0), &ball, at(0.5 + d, 0.5 + d), MAX);
        assert_eq!(m.count, 1);
        assert!((m.normal - Vec2::new(1.0, 1.0).normalize()).length() < 1e-5);
        assert!((m.points[0].separation - 0.01).abs() < 1e-5);
    }

    #[test]
    fn rounded_polygon_against_circle_face() {
        // Box (1, 0.5) rounded by 0.1, a circle of 0.25 at height 0.84: 0.34 above the core's
        // top face, 0.35 of radii: 0.01 deep, the point midway between y = 0.6 and y = 0.59.
        let mut core = Polygon::new_box(1.0, 0.5);
        core.radius = 0.1;
        let ball = Circle { radius: 0.25 };
        let m = collide_polygon_circle(&core, at(0.0, 0.0), &ball, at(0.3, 0.84), MAX);
        assert_eq!(m.count, 1);
        assert!((m.normal - Vec2::Y).length() < 1e-6);
        assert!((m.points[0].separation + 0.01).abs() < 1e-6);
        assert!((m.points[0].anchor_a - Vec2::new(0.3, 0.595)).length() < 1e-6);
    }

    #[test]
    fn box_on_a_segment() {
        // A long segment on the x axis and a unit box 0.01 into it, centred at x = 1.
        let seg = Shape::Segment(Segment {
            point1: Vec2::new(-5.0, 0.0),
            point2: Vec2::new(5.0, 0.0),
        });
        let bx = Shape::Polygon(Polygon::new_box(0.5, 0.5));
        let m = collide(&seg, at(0.0, 0.0), &bx, at(1.0, 0.49), MAX);
        assert_eq!(m.count, 2);
        assert!((m.normal - Vec2::Y).length() < 1e-6);
        for p in m.points() {
            assert!((p.separation + 0.01).abs() < 1e-5);
            assert!((p.anchor_a.y + 0.005).abs() < 1e-5);
        }
        let x = xs(&m);
        assert!(
            (x[0] - 0.5).abs() < 1e-5 && (x[1] - 1.5).abs() < 1e-5,
            "{x:?}"
        );
        // Two segments never meet.
        let m = collide(&seg, at(0.0, 0.0), &seg, xf(0.0, 0.0, 0.5), MAX);
        assert_eq!(m.count, 0);
    }

    #[test]
    fn chain_segment_pushes_only_to_its_right() {
        // The segment (2,0) -> (-2,0) pushes up: its right-hand side is (dy, -dx) = (0, 4).
        let s = chain([4.0, 0.0], [2.0, 0.0], [-2.0, 0.0], [-4.0, 0.0]);
        let ball = Shape::Circle(Circle { radius: 0.5 });
        let m = collide(&s, at(0.0, 0.0), &ball, at(0.0, 0.49), MAX);
        assert_eq!(m.count, 1);
        assert!((m.normal - Vec2::Y).length() < 1e-6);
        assert!((m.points[0].separation + 0.01).abs() < 1e-6);
        // From below, nothing.
        let m = collide(&s, at(0.0, 0.0), &ball, at(0.0, -0.49), MAX);
        assert_eq!(m.count, 0);
        let bx = Shape::Polygon(Polygon::new_box(0.5, 0.5));
        let m = collide(&s, at(0.0, 0.0), &bx, at(0.0, 0.49), MAX);
        assert_eq!(m.count, 2);
        assert!((m.normal - Vec2::Y).length() < 1e-6);
        for p in m.points() {
            assert!((p.separation + 0.01).abs() < 1e-5, "{}", p.separation);
        }
        let m = collide(&s, at(0.0, 0.0), &bx, at(0.0, -0.49), MAX);
        assert_eq!(m.count, 0);
    }

    #[test]
    fn a_centre_past_a_chain_vertex_belongs_to_the_neighbour() {
        // Beyond point1 (2,0) the circle is in the previous segment's region ((4,0) -> (2,0)
        // owns it): this segment reports nothing there, so the joint gives one contact.
        let s = chain([4.0, 0.0], [2.0, 0.0], [-2.0, 0.0], [-4.0, 0.0]);
        let prev = chain([6.0, 0.0], [4.0, 0.0], [2.0, 0.0], [-2.0, 0.0]);
        let ball = Shape::Circle(Circle { radius: 0.5 });
        let m = collide(&s, at(0.0, 0.0), &ball, at(2.3, 0.3), MAX);
        assert_eq!(m.count, 0);
        let m = collide(&prev, at(0.0, 0.0), &ball, at(2.3, 0.3), MAX);
        assert_eq!(m.count, 1);
        assert!((m.normal - Vec2::Y).length() < 1e-6);
    }

    #[test]
    fn a_box_crossing_a_chain_joint_meets_no_edge() {
        // Two collinear segments meet at (0,0). A unit box 0.01 deep in the left one, its
        // right face 0.015 short of the joint: a lone two-sided segment (2,0)-(0,0) would
        // report its end vertex against the box's right face (a sideways normal, the snag
        // that stops a sliding box); the chain segment reports nothing.
        let right = chain([6.0, 0.0], [2.0, 0.0], [0.0, 0.0], [-2.0, 0.0]);
        let bx = Shape::Polygon(Polygon::new_box(0.5, 0.5));
        let pose = at(-0.515, 0.49);
        let lone = Shape::Segment(Segment {
            point1: Vec2::new(2.0, 0.0),
            point2: Vec2::new(0.0, 0.0),
        });
        let snag = collide(&lone, at(0.0, 0.0), &bx, pose, MAX);
        assert!((snag.normal + Vec2::X).length() < 1e-5, "{:?}", snag.normal);
        // The end vertex 0.015 from the face (the clip keeps the far end as well).
        let nearest = snag
            .points()
            .iter()
            .fold(f32::MAX, |s, p| s.min(p.separation));
        assert!((nearest - 0.015).abs() < 1e-5, "{nearest}");
        let m = collide(&right, at(0.0, 0.0), &bx, pose, MAX);
        assert!(
            m.points().is_empty() || (m.normal - Vec2::Y).length() < 1e-5,
            "{m:?}"
        );
        // The left segment holds the box up.
        let left = chain([2.0, 0.0], [0.0, 0.0], [-2.0, 0.0], [-6.0, 0.0]);
        let m = collide(&left, at(0.0, 0.0), &bx, pose, MAX);
        assert_eq!(m.count, 2);
        assert!((m.normal - Vec2::Y).length() < 1e-6);
    }

    #[test]
    fn capsule_lying_on_a_chain() {
        let s = chain([4.0, 0.0], [2.0, 0.0], [-2.0, 0.0], [-4.0, 0.0]);
        let cap = capsule(-1.0, 0.0, 1.0, 0.0, 0.25);
        let m = collide(&s, at(0.0, 0.0), &cap, at(0.0, 0.24), MAX);
        assert_eq!(m.count, 2);
        assert!((m.normal - Vec2::Y).length() < 1e-6);
        for p in m.points() {
            assert!((p.separation + 0.01).abs() < 1e-5, "{}", p.separation);
            // Midway between the chain (y = 0) and the capsule's bottom (y = -0.01).
            assert!((p.anchor_a.y + 0.005).abs() < 1e-5);
        }
        let x = xs(&m);
        assert!(
            (x[0] + 1.0).abs() < 1e-5 && (x[1] - 1.0).abs() < 1e-5,
            "{x:?}"
        );
    }

    #[test]
    fn a_box_past_a_convex_chain_corner_belongs_to_the_next_segment() {
        // A chain turning left at (0,0) — from along -x to along -y — is convex there (a
        // corner of a box-shaped platform, walked clockwise). A box resting against the
        // platform's vertical side is the next segment's contact, not this one's.
        let top = chain([4.0, 0.0], [2.0, 0.0], [0.0, 0.0], [0.0, -2.0]);
        let side = chain([2.0, 0.0], [0.0, 0.0], [0.0, -2.0], [0.0, -4.0]);
        let bx = Shape::Polygon(Polygon::new_box(0.5, 0.5));
        let pose = at(-0.49, -1.0);
        let m = collide(&top, at(0.0, 0.0), &bx, pose, MAX);
        assert_eq!(m.count, 0, "{m:?}");
        let m = collide(&side, at(0.0, 0.0), &bx, pose, MAX);
        assert_eq!(m.count, 2);
        assert!((m.normal + Vec2::X).length() < 1e-5, "{:?}", m.normal);
        for p in m.points() {
            assert!((p.separation + 0.01).abs() < 1e-5, "{}", p.separation);
        }
    }
}
