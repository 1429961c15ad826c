//! Shapes, their mass properties and bounding boxes.
//!
//! Every shape's geometry is centred on its own centroid: circles by definition, boxes by
//! symmetry, and polygons because loading recentres their vertices. Where a shape sits on its
//! body is a transform kept beside it (see `crate::body`); for a body of one shape that
//! transform is the identity and the body's origin is its centre of mass.

use glam::Vec2;

use crate::LINEAR_SLOP;
use crate::error::PolygonError;
use crate::math::{Transform, cross, dot, normalize_and_length, right_perp};
use crate::scene::{MAX_POLYGON_VERTICES, ShapeDef};

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

/// Mass, rotational inertia about the centre of mass, for a given density.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MassData {
    /// kg.
    pub mass: f32,
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
    /// Number of vertices, 3 to 8.
    pub count: usize,
}

impl Polygon {
    /// A box of half extents `hx`, `hy`, centred and axis-aligned in its frame.
    pub fn new_box(hx: f32, hy: f32) -> Polygon {
        let mut p = Polygon {
            vertices: [Vec2::ZERO; MAX_POLYGON_VERTICES],
            normals: [Vec2::ZERO; MAX_POLYGON_VERTICES],
            count: 4,
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

    /// The used vertices.
    #[inline]
    pub fn points(&self) -> &[Vec2] {
        &self.vertices[..self.count]
    }

    /// Mass properties for a density, about the centroid (the origin).
    pub fn mass(&self, density: f32) -> MassData {
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
            inertia: density * inertia,
        }
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
    /// A convex polygon (boxes are polygons too).
    Polygon(Polygon),
}

impl Shape {
    /// Builds the shape from its scene description.
    pub fn from_def(def: &ShapeDef) -> Result<Shape, PolygonError> {
        Ok(match def {
            ShapeDef::Circle { radius } => Shape::Circle(Circle { radius: *radius }),
            ShapeDef::Box { half_extents } => {
                Shape::Polygon(Polygon::new_box(half_extents[0], half_extents[1]))
            }
            ShapeDef::Polygon { vertices } => Shape::Polygon(Polygon::from_vertices(vertices)?),
        })
    }

    /// Mass properties about the centre for a density.
    pub fn mass(&self, density: f32) -> MassData {
        match self {
            Shape::Circle(c) => {
                // Disc: m = ρπr², I = m r²/2.
                let mass = density * std::f32::consts::PI * c.radius * c.radius;
                MassData {
                    mass,
                    inertia: 0.5 * mass * c.radius * c.radius,
                }
            }
            Shape::Polygon(p) => p.mass(density),
        }
    }

    /// Largest distance from the centre to the surface.
    pub fn extent(&self) -> f32 {
        match self {
            Shape::Circle(c) => c.radius,
            Shape::Polygon(p) => p.points().iter().fold(0.0f32, |m, v| m.max(v.length())),
        }
    }

    /// Smallest distance from the centre to the surface (how thin the shape is).
    pub fn min_extent(&self) -> f32 {
        match self {
            Shape::Circle(c) => c.radius,
            Shape::Polygon(p) => {
                let mut m = f32::MAX;
                for i in 0..p.count {
                    m = m.min(dot(p.normals[i], p.vertices[i]));
                }
                m
            }
        }
    }

    /// Tight bounding box at a transform.
    pub fn aabb(&self, xf: Transform) -> Aabb {
        match self {
            Shape::Circle(c) => Aabb {
                min: xf.p - Vec2::splat(c.radius),
                max: xf.p + Vec2::splat(c.radius),
            },
            Shape::Polygon(p) => {
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
}
