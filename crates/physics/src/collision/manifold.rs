//! Contact manifolds for each shape pair: circle–circle, polygon–circle, polygon–polygon.
//!
//! The algorithms follow Box2D v3 (`manifold.c`): points lie midway between the two
//! surfaces with a signed separation, the normal points from A to B, and every point carries
//! a feature id (reference and incident vertex or edge indices) so the solver can carry its
//! impulses over to the next step. Points are kept while their separation is within
//! `max_distance` (the speculative margin), so bodies meet without overlapping.

use glam::Vec2;

use crate::LINEAR_SLOP;
use crate::math::{Transform, dot, normalize_and_length};
use crate::shape::{Circle, Polygon, Shape};

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

/// Computes the manifold between two shapes at their transforms. Polygon–circle expects the
/// polygon as shape A; the world orders each pair so.
pub fn collide(
    shape_a: &Shape,
    xf_a: Transform,
    shape_b: &Shape,
    xf_b: Transform,
    max_distance: f32,
) -> Manifold {
    match (shape_a, shape_b) {
        (Shape::Circle(a), Shape::Circle(b)) => collide_circles(a, xf_a, b, xf_b, max_distance),
        (Shape::Polygon(a), Shape::Circle(b)) => {
            collide_polygon_circle(a, xf_a, b, xf_b, max_distance)
        }
        (Shape::Circle(a), Shape::Polygon(b)) => {
            // Not produced by the world; kept total by flipping.
            let mut m = collide_polygon_circle(b, xf_b, a, xf_a, max_distance);
            flip(&mut m);
            m
        }
        (Shape::Polygon(a), Shape::Polygon(b)) => collide_polygons(a, xf_a, b, xf_b, max_distance),
    }
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
    let (anchor_a, anchor_b) = anchors(xf_a, xf_b, local);
    let mut m = Manifold {
        normal: xf_a.q.apply(normal_local),
        count: 1,
        ..Manifold::default()
    };
    m.points[0] = ManifoldPoint {
        anchor_a,
        anchor_b,
        separation: sep,
        id,
        ..ManifoldPoint::default()
    };
    m
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

/// Polygon (A) against circle (B): face contact or one of the two vertex regions.
pub fn collide_polygon_circle(
    a: &Polygon,
    xf_a: Transform,
    b: &Circle,
    xf_b: Transform,
    max_distance: f32,
) -> Manifold {
    let c = xf_a.apply_inv(xf_b.p);
    let radius = b.radius;
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
            let cb = c - normal * radius;
            single(xf_a, xf_b, normal, (v + cb) * 0.5, sep, 0)
        }
        None => {
            let normal = a.normals[best];
            let ca = c - normal * dot(c - v1, normal);
            let cb = c - normal * radius;
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
            si = si.min(dot(n, *w - v));
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

/// Polygon against polygon: SAT both ways, then clip the incident edge against the
/// reference face (Box2D v3's `b2CollidePolygons` and `b2ClipPolygons`).
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
        nbv[i] = xf.q.apply(b.normals[i]);
    }
    let (va, vb) = (&va[..na], &vb[..nb]);
    let (an, bn) = (&a.normals[..na], &nbv[..nb]);
    let (mut edge_a, sep_a) = find_max_separation(va, an, vb);
    let (mut edge_b, sep_b) = find_max_separation(vb, bn, va);
    if sep_a > max_distance || sep_b > max_distance {
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
    let clipped = || clip(xf_a, xf_b, origin, va, an, vb, bn, edge_a, edge_b, flip);
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
    if distance > max_distance {
        return Manifold::default();
    }
    let m = clipped();
    let min_separation = m.points().iter().fold(f32::MAX, |s, p| s.min(p.separation));
    if distance + 0.1 * LINEAR_SLOP >= min_separation {
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
            let mid = p1 + n * (0.5 * distance);
            single(xf_a, xf_b, n, mid + origin, distance, make_id(k1, k2))
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
    edge_a: usize,
    edge_b: usize,
    flip: bool,
) -> Manifold {
    let ((v1s, n1s, e1), (v2s, e2)) = if flip {
        ((vb, bn, edge_b), (va, edge_a))
    } else {
        ((va, an, edge_a), (vb, edge_b))
    };
    let i11 = e1;
    let i12 = (e1 + 1) % v1s.len();
    let i21 = e2;
    let i22 = (e2 + 1) % v2s.len();
    let normal = n1s[i11];
    let (v11, v12, v21, v22) = (v1s[i11], v1s[i12], v2s[i21], v2s[i22]);
    let tangent = Vec2::new(-normal.y, normal.x);
    let lower1 = 0.0;
    let upper1 = dot(v12 - v11, tangent);
    // The incident edge runs against the tangent (both polygons wind counter-clockwise).
    let upper2 = dot(v21 - v11, tangent);
    let lower2 = dot(v22 - v11, tangent);
    if upper2 < lower1 || upper1 < lower2 {
        return Manifold::default();
    }
    let span = upper2 - lower2;
    let v_lower = if lower2 < lower1 && span > f32::EPSILON {
        v22.lerp(v21, (lower1 - lower2) / span)
    } else {
        v22
    };
    let v_upper = if upper2 > upper1 && span > f32::EPSILON {
        v22.lerp(v21, (upper1 - lower2) / span)
    } else {
        v21
    };
    let sep_lower = dot(v_lower - v11, normal);
    let sep_upper = dot(v_upper - v11, normal);
    // Midway between the surfaces.
    let p_lower = v_lower - normal * (0.5 * sep_lower) + origin;
    let p_upper = v_upper - normal * (0.5 * sep_upper) + origin;
    let (n_ab, pts) = if flip {
        (
            -normal,
            [
                (p_upper, sep_upper, make_id(i21, i12)),
                (p_lower, sep_lower, make_id(i22, i11)),
            ],
        )
    } else {
        (
            normal,
            [
                (p_lower, sep_lower, make_id(i11, i22)),
                (p_upper, sep_upper, make_id(i12, i21)),
            ],
        )
    };
    let mut m = Manifold {
        normal: xf_a.q.apply(n_ab),
        count: 2,
        ..Manifold::default()
    };
    for (k, (local, sep, id)) in pts.into_iter().enumerate() {
        let (anchor_a, anchor_b) = anchors(xf_a, xf_b, local);
        m.points[k] = ManifoldPoint {
            anchor_a,
            anchor_b,
            separation: sep,
            id,
            ..ManifoldPoint::default()
        };
    }
    m
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
}
