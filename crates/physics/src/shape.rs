//! Shapes, their mass properties and bounding boxes.
//!
//! Every shape with area is centred on its own centroid: circles by definition, boxes by
//! symmetry, polygons and capsules because loading recentres them. Segments and chain
//! segments have no area (and no mass) and keep the points they were given. Where a shape sits
//! on its body is a transform kept beside it (see `crate::body`); for a body of one shape that
//! transform is the identity and the body's origin is its centre of mass.
//!
//! The shape types are listed in Box2D v3's order (circle, capsule, polygon, segment, chain
//! segment, `b2ShapeType`): a contact's shape A is the one later in that order, so each pair
//! has one manifold routine.

use glam::Vec2;

use crate::LINEAR_SLOP;
use crate::def::{MAX_POLYGON_VERTICES, ShapeDef};
use crate::error::PolygonError;
use crate::math::{Transform, cross, dot, normalize_and_length, right_perp};

/// An axis-aligned bounding box.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Aabb {
    /// Lower corner.
    pub min: Vec2,
    /// Upper corner.
    pub max: Vec2,
}

impl Aabb {
    /// A box that overlaps every finite box.
    pub const EVERYWHERE: Aabb = Aabb {
        min: Vec2::splat(f32::MIN),
        max: Vec2::splat(f32::MAX),
    };

    /// A box that overlaps no box, not even [`Aabb::EVERYWHERE`] (its corners are inverted
    /// infinities).
    pub const NOWHERE: Aabb = Aabb {
        min: Vec2::splat(f32::INFINITY),
        max: Vec2::splat(f32::NEG_INFINITY),
    };

    /// Whether two boxes overlap (touching counts).
    #[inline]
    pub fn overlaps(&self, other: &Aabb) -> bool {
        !(other.min.x > self.max.x
            || other.min.y > self.max.y
            || self.min.x > other.max.x
            || self.min.y > other.max.y)
    }

    /// Whether `other` lies entirely inside `self`.
    #[inline]
    pub fn contains(&self, other: &Aabb) -> bool {
        self.min.x <= other.min.x
            && self.min.y <= other.min.y
            && other.max.x <= self.max.x
            && other.max.y <= self.max.y
    }

    /// The smallest box holding both.
    #[inline]
    pub fn union(&self, other: &Aabb) -> Aabb {
        Aabb {
            min: self.min.min(other.min),
            max: self.max.max(other.max),
        }
    }

    /// Grown by `margin` on every side.
    #[inline]
    pub fn grown(&self, margin: f32) -> Aabb {
        let m = Vec2::splat(margin);
        Aabb {
            min: self.min - m,
            max: self.max + m,
        }
    }

    /// Centre point.
    #[inline]
    pub fn center(&self) -> Vec2 {
        (self.min + self.max) * 0.5
    }

    /// Half the perimeter; the surface-area heuristic's cost in 2D.
    #[inline]
    pub fn perimeter(&self) -> f32 {
        let d = self.max - self.min;
        2.0 * (d.x + d.y)
    }
}

/// Mass, centre of mass and rotational inertia about it: a shape's for a given density, or
/// a body's ([`crate::World::mass_data`], [`crate::World::set_mass_data`]; Box2D's
/// `b2MassData`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MassData {
    /// kg.
    pub mass: f32,
    /// The centre of mass in the shape's frame (the origin for every shape loading centres;
    /// a rounded polygon's mass, as Box2D approximates it, can lie slightly off), or in the
    /// body's frame for a body's.
    pub center: Vec2,
    /// kg·m² about the centre of mass.
    pub inertia: f32,
}

/// A disc centred on its body.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Circle {
    /// Radius (m).
    pub radius: f32,
}

/// A convex polygon centred on its centroid, counter-clockwise, with outward edge normals.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Polygon {
    /// Vertices; only the first `count` are used.
    pub vertices: [Vec2; MAX_POLYGON_VERTICES],
    /// `normals[i]` is the outward unit normal of the edge from vertex `i` to `i + 1`.
    pub normals: [Vec2; MAX_POLYGON_VERTICES],
    /// Number of vertices: 3 to 8 for a polygon, 2 for a capsule or segment handed to the
    /// polygon routines ([`Polygon::capsule`]).
    pub count: usize,
    /// Rounding radius (m): the shape is every point within this distance of the polygon.
    pub radius: f32,
}

impl Polygon {
    /// A box of half extents `hx`, `hy`, centred and axis-aligned in its frame.
    pub fn new_box(hx: f32, hy: f32) -> Polygon {
        let mut p = Polygon {
            vertices: [Vec2::ZERO; MAX_POLYGON_VERTICES],
            normals: [Vec2::ZERO; MAX_POLYGON_VERTICES],
            count: 4,
            radius: 0.0,
        };
        p.vertices[..4].copy_from_slice(&[
            Vec2::new(-hx, -hy),
            Vec2::new(hx, -hy),
            Vec2::new(hx, hy),
            Vec2::new(-hx, hy),
        ]);
        p.normals[..4].copy_from_slice(&[
            Vec2::new(0.0, -1.0),
            Vec2::new(1.0, 0.0),
            Vec2::new(0.0, 1.0),
            Vec2::new(-1.0, 0.0),
        ]);
        p
    }

    /// Checks a user polygon (3 to 8 finite vertices, counter-clockwise, strictly convex,
    /// edges longer than the linear slop) and recentres it on its centroid.
    pub fn from_vertices(points: &[[f32; 2]]) -> Result<Polygon, PolygonError> {
        Polygon::centred(points).map(|(p, _)| p)
    }

    /// As [`Polygon::from_vertices`], and where the centroid was in the points' frame.
    pub fn centred(points: &[[f32; 2]]) -> Result<(Polygon, Vec2), PolygonError> {
        let n = points.len();
        if !(3..=MAX_POLYGON_VERTICES).contains(&n) {
            return Err(PolygonError::VertexCount(n));
        }
        let mut v = [Vec2::ZERO; MAX_POLYGON_VERTICES];
        for (i, p) in points.iter().enumerate() {
            if !(p[0].is_finite() && p[1].is_finite()) {
                return Err(PolygonError::NonFinite(i));
            }
            v[i] = Vec2::new(p[0], p[1]);
        }
        for i in 0..n {
            let j = (i + 1) % n;
            // Box2D welds vertices closer than half a slop; we refuse them instead.
            if (v[j] - v[i]).length() < 0.5 * LINEAR_SLOP {
                return Err(PolygonError::Degenerate(i, j));
            }
        }
        let area = signed_area(&v[..n]);
        // NaN-safe: a NaN area is refused too.
        if area.is_nan() || area <= 0.0 {
            return Err(PolygonError::ZeroArea);
        }
        for i in 0..n {
            let a = v[i];
            let b = v[(i + 1) % n];
            let c = v[(i + 2) % n];
            let turn = cross(b - a, c - b);
            // Relative tolerance: a turn this small means three collinear points.
            let tol = 1.0e-6 * (b - a).length() * (c - b).length().max(1e-12);
            if turn < -tol {
                return Err(PolygonError::NotConvex((i + 1) % n));
            }
            if turn <= tol {
                return Err(PolygonError::Degenerate(i, (i + 1) % n));
            }
        }
        let centroid = polygon_centroid(&v[..n]);
        let mut p = Polygon {
            vertices: [Vec2::ZERO; MAX_POLYGON_VERTICES],
            normals: [Vec2::ZERO; MAX_POLYGON_VERTICES],
            count: n,
            radius: 0.0,
        };
        for i in 0..n {
            p.vertices[i] = v[i] - centroid;
        }
        for i in 0..n {
            let edge = p.vertices[(i + 1) % n] - p.vertices[i];
            p.normals[i] = normalize_and_length(right_perp(edge)).0;
        }
        Ok((p, centroid))
    }

    /// The segment `p1`–`p2` rounded by `radius`, as a polygon of two vertices whose two
    /// "edges" are the segment's two sides (Box2D's `b2MakeCapsule` in `manifold.c`): capsules
    /// and segments go through the polygon routines this way. The points must be apart.
    pub fn capsule(p1: Vec2, p2: Vec2, radius: f32) -> Polygon {
        let normal = right_perp(normalize_and_length(p2 - p1).0);
        let mut p = Polygon {
            vertices: [Vec2::ZERO; MAX_POLYGON_VERTICES],
            normals: [Vec2::ZERO; MAX_POLYGON_VERTICES],
            count: 2,
            radius,
        };
        p.vertices[0] = p1;
        p.vertices[1] = p2;
        p.normals[0] = normal;
        p.normals[1] = -normal;
        p
    }

    /// The used vertices.
    #[inline]
    pub fn points(&self) -> &[Vec2] {
        &self.vertices[..self.count]
    }

    /// Mass properties for a density. Sharp polygons: about the centroid (the origin),
    /// exactly. Rounded ones as Box2D approximates them (`b2ComputePolygonMass`): each vertex
    /// pushed out along its corner's bisector by 1.412 times the radius, then the polygon of
    /// those vertices.
    pub fn mass(&self, density: f32) -> MassData {
        if self.radius > 0.0 {
            return self.rounded_mass(density);
        }
        self.sharp_mass(density)
    }

    fn rounded_mass(&self, density: f32) -> MassData {
        let n = self.count;
        let mut pushed = [Vec2::ZERO; MAX_POLYGON_VERTICES];
        for (i, out) in pushed[..n].iter_mut().enumerate() {
            let prev = self.normals[(i + n - 1) % n];
            let mid = normalize_and_length(prev + self.normals[i]).0;
            *out = self.vertices[i] + mid * (1.412 * self.radius);
        }
        // Triangle fan from the first pushed vertex, then the inertia shifted to the centroid.
        let origin = pushed[0];
        let (mut area, mut center, mut inertia) = (0.0f32, Vec2::ZERO, 0.0f32);
        for i in 1..n - 1 {
            let e1 = pushed[i] - origin;
            let e2 = pushed[i + 1] - origin;
            let d = cross(e1, e2);
            let tri = 0.5 * d;
            area += tri;
            center += (e1 + e2) * (tri / 3.0);
            let intx2 = e1.x * e1.x + e2.x * e1.x + e2.x * e2.x;
            let inty2 = e1.y * e1.y + e2.y * e1.y + e2.y * e2.y;
            inertia += (0.25 / 3.0) * d * (intx2 + inty2);
        }
        let offset = center / area;
        let mass = density * area;
        MassData {
            mass,
            center: origin + offset,
            inertia: density * inertia - mass * offset.length_squared(),
        }
    }

    fn sharp_mass(&self, density: f32) -> MassData {
        // Triangle fan from the centroid; each triangle's inertia about the origin is
        // (area/6)·(|e1|² + e1·e2 + |e2|²) (the polygon second moment, e.g. Box2D's
        // b2ComputePolygonMass).
        let mut area = 0.0;
        let mut inertia = 0.0;
        let n = self.count;
        for i in 0..n {
            let e1 = self.vertices[i];
            let e2 = self.vertices[(i + 1) % n];
            let d = cross(e1, e2);
            let tri = 0.5 * d;
            area += tri;
            let intx2 = e1.x * e1.x + e2.x * e1.x + e2.x * e2.x;
            let inty2 = e1.y * e1.y + e2.y * e1.y + e2.y * e2.y;
            inertia += (0.25 / 3.0) * d * (intx2 + inty2);
        }
        MassData {
            mass: density * area,
            center: Vec2::ZERO,
            inertia: density * inertia,
        }
    }
}

/// A rectangle capped by two half discs: every point within `radius` of the segment between
/// the two centres. Loading centres it on its midpoint.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Capsule {
    /// One end of the core segment.
    pub center1: Vec2,
    /// The other end.
    pub center2: Vec2,
    /// Radius (m), > 0.
    pub radius: f32,
}

impl Capsule {
    /// Mass properties for a density (Box2D's `b2ComputeCapsuleMass`: a rectangle of
    /// length × 2r and two half discs, each moved to its end by the parallel-axis theorem
    /// from its own centroid, 4r/3π from the flat side).
    pub fn mass(&self, density: f32) -> MassData {
        let r = self.radius;
        let length = (self.center2 - self.center1).length();
        let circle_mass = density * std::f32::consts::PI * r * r;
        let box_mass = density * 2.0 * r * length;
        let lc = 4.0 * r / (3.0 * std::f32::consts::PI);
        let h = 0.5 * length;
        let circle_inertia = circle_mass * (0.5 * r * r + h * h + 2.0 * h * lc);
        let box_inertia = box_mass * (4.0 * r * r + length * length) / 12.0;
        MassData {
            mass: circle_mass + box_mass,
            center: (self.center1 + self.center2) * 0.5,
            inertia: circle_inertia + box_inertia,
        }
    }
}

/// A line segment, two-sided, with no area. A static body's ground or wall.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Segment {
    /// One end.
    pub point1: Vec2,
    /// The other end.
    pub point2: Vec2,
}

/// One segment of a chain: one-sided (it pushes only towards its right-hand side, the side of
/// (dy, −dx) for a segment from `point1` to `point1 + (dx, dy)`), and it knows its
/// neighbours' far ends (`ghost1` before `point1`, `ghost2` after `point2`) so that a body
/// sliding across the joint between two segments meets no edge there (Box2D's chain
/// segments; see "Ghost collisions", box2d.org/posts/2020/06/ghost-collisions).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ChainSegment {
    /// The previous segment's start.
    pub ghost1: Vec2,
    /// The segment itself.
    pub segment: Segment,
    /// The next segment's end.
    pub ghost2: Vec2,
}

/// A chain's points made into its segments (Box2D's `b2CreateChain`): a loop of n points
/// gives n segments, each with its neighbours as ghosts; an open chain gives n − 3, its first
/// and last points serving only as the ghosts of the end segments.
pub fn chain_segments(points: &[Vec2], looped: bool) -> Vec<ChainSegment> {
    let n = points.len();
    if looped {
        (0..n)
            .map(|i| ChainSegment {
                ghost1: points[(i + n - 1) % n],
                segment: Segment {
                    point1: points[i],
                    point2: points[(i + 1) % n],
                },
                ghost2: points[(i + 2) % n],
            })
            .collect()
    } else {
        (0..n.saturating_sub(3))
            .map(|i| ChainSegment {
                ghost1: points[i],
                segment: Segment {
                    point1: points[i + 1],
                    point2: points[i + 2],
                },
                ghost2: points[i + 3],
            })
            .collect()
    }
}

fn signed_area(v: &[Vec2]) -> f32 {
    let n = v.len();
    let mut a = 0.0;
    for i in 0..n {
        a += cross(v[i] - v[0], v[(i + 1) % n] - v[0]);
    }
    0.5 * a
}

fn polygon_centroid(v: &[Vec2]) -> Vec2 {
    // Triangle fan from vertex 0, shifted to it to limit round-off.
    let origin = v[0];
    let mut c = Vec2::ZERO;
    let mut area = 0.0;
    for i in 1..v.len() - 1 {
        let e1 = v[i] - origin;
        let e2 = v[i + 1] - origin;
        let a = 0.5 * cross(e1, e2);
        c += (e1 + e2) * (a / 3.0);
        area += a;
    }
    origin + c * (1.0 / area)
}

/// A body's collision shape.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Shape {
    /// A disc.
    Circle(Circle),
    /// A rounded segment.
    Capsule(Capsule),
    /// A convex polygon, maybe rounded (boxes are polygons too).
    Polygon(Polygon),
    /// A two-sided segment without area.
    Segment(Segment),
    /// One segment of a chain: one-sided, without area.
    ChainSegment(ChainSegment),
}

impl Shape {
    /// Builds the shape from its scene description. A chain is several shapes: see
    /// [`chain_segments`]; here it is refused.
    pub fn from_def(def: &ShapeDef) -> Result<Shape, PolygonError> {
        Shape::centred(def).map(|(s, _)| s)
    }

    /// As [`Shape::from_def`], and where the shape's centre was in the description's frame:
    /// polygons and capsules are recentred on their centroid; segments keep their points.
    pub fn centred(def: &ShapeDef) -> Result<(Shape, Vec2), PolygonError> {
        Ok(match def {
            ShapeDef::Circle { radius } => (Shape::Circle(Circle { radius: *radius }), Vec2::ZERO),
            ShapeDef::Box {
                half_extents,
                radius,
            } => {
                let mut p = Polygon::new_box(half_extents[0], half_extents[1]);
                p.radius = *radius;
                (Shape::Polygon(p), Vec2::ZERO)
            }
            ShapeDef::Polygon { vertices, radius } => {
                let (mut p, centroid) = Polygon::centred(vertices)?;
                p.radius = *radius;
                (Shape::Polygon(p), centroid)
            }
            ShapeDef::Capsule {
                center1,
                center2,
                radius,
            } => {
                let (c1, c2) = (Vec2::from(*center1), Vec2::from(*center2));
                if !(c1.is_finite() && c2.is_finite()) {
                    return Err(PolygonError::NonFinite(0));
                }
                if (c2 - c1).length() < LINEAR_SLOP {
                    return Err(PolygonError::Degenerate(0, 1));
                }
                let mid = (c1 + c2) * 0.5;
                let capsule = Capsule {
                    center1: c1 - mid,
                    center2: c2 - mid,
                    radius: *radius,
                };
                (Shape::Capsule(capsule), mid)
            }
            ShapeDef::Segment { point1, point2 } => {
                let (p1, p2) = (Vec2::from(*point1), Vec2::from(*point2));
                if !(p1.is_finite() && p2.is_finite()) {
                    return Err(PolygonError::NonFinite(0));
                }
                if (p2 - p1).length() < LINEAR_SLOP {
                    return Err(PolygonError::Degenerate(0, 1));
                }
                let segment = Segment {
                    point1: p1,
                    point2: p2,
                };
                (Shape::Segment(segment), Vec2::ZERO)
            }
            ShapeDef::Chain { .. } => return Err(PolygonError::VertexCount(0)),
        })
    }

    /// Whether the shape has area (and so mass). Segments and chains have none.
    pub fn has_area(&self) -> bool {
        matches!(
            self,
            Shape::Circle(_) | Shape::Capsule(_) | Shape::Polygon(_)
        )
    }

    /// The shape's place in Box2D's order of shape types (`b2ShapeType`): a contact's
    /// shape A is the one of higher rank.
    pub fn rank(&self) -> u8 {
        match self {
            Shape::Circle(_) => 0,
            Shape::Capsule(_) => 1,
            Shape::Polygon(_) => 2,
            Shape::Segment(_) => 3,
            Shape::ChainSegment(_) => 4,
        }
    }

    /// How round the shape is: a circle's or capsule's radius, a polygon's rounding, 0 for a
    /// segment (Box2D's `b2GetShapeRadius`, the lever of rolling resistance).
    pub fn radius(&self) -> f32 {
        match self {
            Shape::Circle(c) => c.radius,
            Shape::Capsule(c) => c.radius,
            Shape::Polygon(p) => p.radius,
            Shape::Segment(_) | Shape::ChainSegment(_) => 0.0,
        }
    }

    /// Whether two shapes of these kinds can touch: segments and chain segments never meet
    /// each other (neither has an inside; Box2D registers no routine for them).
    pub fn pair_collides(a: &Shape, b: &Shape) -> bool {
        a.has_area() || b.has_area()
    }

    /// Mass properties about the centre for a density.
    pub fn mass(&self, density: f32) -> MassData {
        match self {
            Shape::Circle(c) => {
                // Disc: m = ρπr², I = m r²/2.
                let mass = density * std::f32::consts::PI * c.radius * c.radius;
                MassData {
                    mass,
                    center: Vec2::ZERO,
                    inertia: 0.5 * mass * c.radius * c.radius,
                }
            }
            Shape::Capsule(c) => c.mass(density),
            Shape::Polygon(p) => p.mass(density),
            Shape::Segment(_) | Shape::ChainSegment(_) => MassData {
                mass: 0.0,
                center: Vec2::ZERO,
                inertia: 0.0,
            },
        }
    }

    /// Largest distance from the shape's origin to its surface.
    pub fn extent(&self) -> f32 {
        match self {
            Shape::Circle(c) => c.radius,
            Shape::Capsule(c) => c.center1.length().max(c.center2.length()) + c.radius,
            Shape::Polygon(p) => {
                p.points().iter().fold(0.0f32, |m, v| m.max(v.length())) + p.radius
            }
            Shape::Segment(s) => s.point1.length().max(s.point2.length()),
            Shape::ChainSegment(c) => c.segment.point1.length().max(c.segment.point2.length()),
        }
    }

    /// Smallest distance from the centre to the surface (how thin the shape is; Box2D's
    /// `b2ComputeShapeExtent`). Zero for the shapes without area.
    pub fn min_extent(&self) -> f32 {
        match self {
            Shape::Circle(c) => c.radius,
            Shape::Capsule(c) => c.radius,
            Shape::Polygon(p) => {
                let mut m = f32::MAX;
                for i in 0..p.count {
                    m = m.min(dot(p.normals[i], p.vertices[i]));
                }
                m + p.radius
            }
            Shape::Segment(_) | Shape::ChainSegment(_) => 0.0,
        }
    }

    /// Tight bounding box at a transform.
    pub fn aabb(&self, xf: Transform) -> Aabb {
        let points = |pts: &[Vec2], radius: f32| {
            let first = xf.apply(pts[0]);
            let (mut min, mut max) = (first, first);
            for v in &pts[1..] {
                let w = xf.apply(*v);
                min = min.min(w);
                max = max.max(w);
            }
            let r = Vec2::splat(radius);
            Aabb {
                min: min - r,
                max: max + r,
            }
        };
        match self {
            Shape::Circle(c) => Aabb {
                min: xf.p - Vec2::splat(c.radius),
                max: xf.p + Vec2::splat(c.radius),
            },
            Shape::Capsule(c) => points(&[c.center1, c.center2], c.radius),
            Shape::Polygon(p) if p.radius == 0.0 => {
                let first = xf.apply(p.vertices[0]);
                let mut min = first;
                let mut max = first;
                for v in &p.vertices[1..p.count] {
                    let w = xf.apply(*v);
                    min = min.min(w);
                    max = max.max(w);
                }
                Aabb { min, max }
            }
            Shape::Polygon(p) => points(p.points(), p.radius),
            Shape::Segment(s) => points(&[s.point1, s.point2], 0.0),
            Shape::ChainSegment(c) => points(&[c.segment.point1, c.segment.point2], 0.0),
        }
    }

    /// Whether a point in the shape's frame lies inside it (segments have no inside).
    pub fn contains(&self, local: Vec2) -> bool {
        match self {
            Shape::Circle(c) => local.length_squared() <= c.radius * c.radius,
            Shape::Capsule(c) => {
                let (a, b) = (c.center1, c.center2);
                let t = (dot(local - a, b - a) / (b - a).length_squared()).clamp(0.0, 1.0);
                (local - (a + (b - a) * t)).length_squared() <= c.radius * c.radius
            }
            Shape::Polygon(p) => {
                // Inside the core, or within the radius of one of its edges.
                let inside = (0..p.count).all(|k| dot(p.normals[k], local - p.vertices[k]) <= 0.0);
                inside
                    || (p.radius > 0.0
                        && (0..p.count).any(|k| {
                            let a = p.vertices[k];
                            let b = p.vertices[(k + 1) % p.count];
                            let t =
                                (dot(local - a, b - a) / (b - a).length_squared()).clamp(0.0, 1.0);
                            (local - (a + (b - a) * t)).length_squared() <= p.radius * p.radius
                        }))
            }
            Shape::Segment(_) | Shape::ChainSegment(_) => false,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f32::consts::PI;

    fn rel(a: f32, b: f32) -> f32 {
        (a - b).abs() / b.abs()
    }

    #[test]
    fn circle_mass_and_inertia_match_textbook() {
        let s = Shape::Circle(Circle { radius: 0.5 });
        let m = s.mass(2.0);
        // m = ρπr² = 2π/4; I = m r² / 2. f32 arithmetic: relative error ~1e-7.
        assert!(rel(m.mass, 2.0 * PI * 0.25) < 1e-6);
        assert!(rel(m.inertia, 0.5 * m.mass * 0.25) < 1e-6);
    }

    #[test]
    fn box_mass_and_inertia_match_textbook() {
        let s = Shape::from_def(&ShapeDef::Box {
            half_extents: [1.5, 0.5],
            radius: 0.0,
        })
        .unwrap();
        let m = s.mass(3.0);
        let (w, h) = (3.0f32, 1.0f32);
        // m = ρwh, I = m(w² + h²)/12 (the seed's formula); fan sums in f32: ~1e-6 relative.
        assert!(rel(m.mass, 3.0 * w * h) < 1e-6);
        assert!(rel(m.inertia, m.mass * (w * w + h * h) / 12.0) < 1e-5);
    }

    #[test]
    fn triangle_mass_and_inertia_match_textbook() {
        // Right triangle legs a=3, b=2 at the origin: area ab/2; inertia about the centroid
        // is m(a² + b²)/18 (polar moment of a right triangle).
        let p = Polygon::from_vertices(&[[0.0, 0.0], [3.0, 0.0], [0.0, 2.0]]).unwrap();
        let m = p.mass(1.0);
        assert!(rel(m.mass, 3.0) < 1e-6);
        assert!(
            rel(m.inertia, 3.0 * (9.0 + 4.0) / 18.0) < 1e-5,
            "{}",
            m.inertia
        );
        // Recentred on the centroid (1, 2/3).
        assert!((p.vertices[0] - Vec2::new(-1.0, -2.0 / 3.0)).length() < 1e-6);
    }

    #[test]
    fn regular_hexagon_inertia() {
        // Regular hexagon of side s: area (3√3/2)s², I = (5/8)·m·s²... polar moment about the
        // centre is (5√3/8)·s⁴·ρ... i.e. I = m·5s²/12.
        let s = 0.8f32;
        let verts: Vec<[f32; 2]> = (0..6)
            .map(|i| {
                let a = i as f32 * PI / 3.0;
                [s * a.cos(), s * a.sin()]
            })
            .collect();
        let p = Polygon::from_vertices(&verts).unwrap();
        let m = p.mass(1.0);
        assert!(rel(m.mass, 1.5 * 3f32.sqrt() * s * s) < 1e-5);
        assert!(rel(m.inertia, m.mass * 5.0 * s * s / 12.0) < 1e-5);
    }

    #[test]
    fn bad_polygons_are_refused() {
        assert_eq!(
            Polygon::from_vertices(&[[0.0, 0.0], [1.0, 0.0]]),
            Err(PolygonError::VertexCount(2))
        );
        // Clockwise square.
        assert_eq!(
            Polygon::from_vertices(&[[0.0, 0.0], [0.0, 1.0], [1.0, 1.0], [1.0, 0.0]]),
            Err(PolygonError::ZeroArea)
        );
        // Concave arrow head.
        assert!(matches!(
            Polygon::from_vertices(&[[0.0, 0.0], [2.0, 0.0], [1.0, 0.2], [1.0, 2.0]]),
            Err(PolygonError::NotConvex(_))
        ));
        // Collinear points: zero area.
        assert_eq!(
            Polygon::from_vertices(&[[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]),
            Err(PolygonError::ZeroArea)
        );
        // A duplicated vertex.
        assert!(matches!(
            Polygon::from_vertices(&[[0.0, 0.0], [1.0, 0.0], [1.0, 0.0], [0.0, 1.0]]),
            Err(PolygonError::Degenerate(..))
        ));
        assert_eq!(
            Polygon::from_vertices(&[[0.0, f32::NAN], [1.0, 0.0], [0.0, 1.0]]),
            Err(PolygonError::NonFinite(0))
        );
    }

    #[test]
    fn extents() {
        let s = Shape::Polygon(Polygon::new_box(1.0, 0.25));
        // Exact: the half extents and the half diagonal.
        assert_eq!(s.min_extent(), 0.25);
        assert!((s.extent() - (1.0f32 + 0.0625).sqrt()).abs() < 1e-6);
        let c = Shape::Circle(Circle { radius: 0.3 });
        assert_eq!((c.min_extent(), c.extent()), (0.3, 0.3));
    }

    #[test]
    fn normals_point_outward() {
        let p = Polygon::new_box(1.0, 2.0);
        for i in 0..4 {
            let mid = (p.vertices[i] + p.vertices[(i + 1) % 4]) * 0.5;
            assert!(dot(p.normals[i], mid) > 0.0);
        }
        let q =
            Polygon::from_vertices(&[[-1.0, -2.0], [1.0, -2.0], [1.0, 2.0], [-1.0, 2.0]]).unwrap();
        assert_eq!(p.normals[..4], q.normals[..4]);
    }

    #[test]
    fn capsule_mass_and_inertia_match_closed_form() {
        // Core length L = 2, radius r = 0.5, density 1: a 2 × 1 rectangle (m = 2) and a disc
        // (m = π/4). Each half disc (mass m_c/2) has inertia (m_c/2)·r²/2 about its flat
        // side's centre and its centroid lies 4r/3π from it; moved to the capsule's centre,
        // L/2 + 4r/3π away: I = m_c(r²/2 + L²/4 + 4Lr/3π) + m_rect(L² + 4r²)/12.
        let c = Capsule {
            center1: Vec2::new(-1.0, 0.0),
            center2: Vec2::new(1.0, 0.0),
            radius: 0.5,
        };
        let (l, r) = (2.0f64, 0.5f64);
        let m_c = std::f64::consts::PI * r * r;
        let m_rect = l * 2.0 * r;
        let inertia = m_c
            * (r * r / 2.0 + l * l / 4.0 + 4.0 * l * r / (3.0 * std::f64::consts::PI))
            + m_rect * (l * l + 4.0 * r * r) / 12.0;
        let md = Shape::Capsule(c).mass(1.0);
        // f32 sums of a few terms: 1e-6 relative.
        assert!(rel(md.mass, (m_c + m_rect) as f32) < 1e-6);
        assert!(rel(md.inertia, inertia as f32) < 1e-6, "{}", md.inertia);
        assert_eq!(md.center, Vec2::ZERO);
    }

    #[test]
    fn rounded_box_mass_is_box2ds_approximation() {
        // A unit box rounded by 0.1: Box2D pushes each corner out by 1.412·r along the
        // diagonal, 0.9984·r on each axis, so the mass is that of a square of side
        // 1 + 2·0.9984·r; the true area (1 + 4r + πr²) is within 1 % of it.
        let def = ShapeDef::Box {
            half_extents: [0.5, 0.5],
            radius: 0.1,
        };
        let md = Shape::from_def(&def).unwrap().mass(1.0);
        let side = 1.0 + 2.0 * 1.412 * 0.1 / 2f32.sqrt();
        assert!(rel(md.mass, side * side) < 1e-5, "{}", md.mass);
        // A square's polar moment: m·side²/6.
        assert!(rel(md.inertia, md.mass * side * side / 6.0) < 1e-4);
        assert!(md.center.length() < 1e-6);
        let exact = 1.0 + 4.0 * 0.1 + PI * 0.01;
        assert!(rel(md.mass, exact) < 0.01);
    }

    #[test]
    fn chains_become_segments_with_their_neighbours_as_ghosts() {
        let pts: Vec<Vec2> = (0..5).map(|i| Vec2::new(i as f32, 0.0)).collect();
        // Open: 5 points, 2 segments; the end points only shape the end segments.
        let open = chain_segments(&pts, false);
        assert_eq!(open.len(), 2);
        assert_eq!(open[0].ghost1, pts[0]);
        assert_eq!(
            (open[0].segment.point1, open[0].segment.point2),
            (pts[1], pts[2])
        );
        assert_eq!(open[1].ghost2, pts[4]);
        // A loop: one segment per point, wrapping round.
        let looped = chain_segments(&pts, true);
        assert_eq!(looped.len(), 5);
        assert_eq!(looped[0].ghost1, pts[4]);
        assert_eq!(looped[4].segment.point2, pts[0]);
        assert_eq!(looped[4].ghost2, pts[1]);
        // No area, no mass.
        let s = Shape::ChainSegment(open[0]);
        assert!(!s.has_area());
        assert_eq!(s.mass(5.0).mass, 0.0);
    }

    #[test]
    fn capsules_are_centred_on_their_midpoint() {
        let def = ShapeDef::Capsule {
            center1: [1.0, 2.0],
            center2: [3.0, 2.0],
            radius: 0.5,
        };
        let (shape, centre) = Shape::centred(&def).unwrap();
        assert_eq!(centre, Vec2::new(2.0, 2.0));
        let Shape::Capsule(c) = shape else {
            panic!("{shape:?}")
        };
        assert_eq!(
            (c.center1, c.center2),
            (Vec2::new(-1.0, 0.0), Vec2::new(1.0, 0.0))
        );
        // Extents: the far end plus the radius; the thinnest is the radius.
        assert_eq!(shape.extent(), 1.5);
        assert_eq!(shape.min_extent(), 0.5);
        assert!(shape.contains(Vec2::new(1.4, 0.0)) && !shape.contains(Vec2::new(1.0, 0.6)));
        let b = shape.aabb(Transform::IDENTITY);
        assert_eq!((b.min, b.max), (Vec2::new(-1.5, -0.5), Vec2::new(1.5, 0.5)));
    }
}
