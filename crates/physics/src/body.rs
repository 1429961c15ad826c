//! A body's mass data: the one place mass, centre of mass, rotational inertia and extents are
//! computed from a body's shapes (the world calls it whenever a body's shapes or kind change,
//! and refreshes every copy from it).

use glam::Vec2;

use crate::def::{BodyDef, ResolvedPart, ShapeDef};
use crate::error::PolygonError;
use crate::math::{Rot, Transform};
use crate::shape::{Shape, chain_segments};

mod state;
pub use state::BodyState;

/// A body's mass data, from all its shapes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyMass {
    /// kg (0 when no shape has density).
    pub mass: f32,
    /// m² of the shapes with area, summed.
    pub area: f32,
    /// Centre of mass in the body's frame (the origin when the mass is 0).
    pub center: Vec2,
    /// kg·m² about the centre of mass (parallel axis theorem over the shapes).
    pub inertia: f32,
    /// Largest distance from the centre of mass to a shape's surface.
    pub extent: f32,
    /// Smallest distance from a shape's centre to its surface (how thin the body is).
    pub min_extent: f32,
}

/// A part's shapes (one, or a chain's segments), each centred on its own centroid where it
/// has area, and where each sits in the body's frame. A body of one shape (`shape`) puts it
/// at the origin as it is; a part of `shapes` at its offset and angle, a polygon's or
/// capsule's centroid carried into the offset (the contract: "a polygon in a part is not
/// recentred").
pub fn part_geometry(part: &ResolvedPart<'_>) -> Result<Vec<(Shape, Transform)>, PolygonError> {
    let q = if part.single {
        Rot::IDENTITY
    } else {
        Rot::from_angle(part.angle)
    };
    let offset = if part.single {
        Vec2::ZERO
    } else {
        Vec2::from(part.offset)
    };
    if let ShapeDef::Chain { points, looped } = part.shape {
        if points.len() < 4 {
            return Err(PolygonError::VertexCount(points.len()));
        }
        let points: Vec<Vec2> = points.iter().map(|p| Vec2::from(*p)).collect();
        // A body of one chain gets the identity: a single part's offset and angle are zeros.
        let local = Transform { p: offset, q };
        return Ok(chain_segments(&points, *looped)
            .into_iter()
            .map(|c| (Shape::ChainSegment(c), local))
            .collect());
    }
    let (shape, centroid) = Shape::centred(part.shape)?;
    if part.single {
        // A body of one shape: its position is the shape's centre (of mass, where it has one).
        return Ok(vec![(shape, Transform::IDENTITY)]);
    }
    let local = Transform {
        p: offset + q.apply(centroid),
        q,
    };
    Ok(vec![(shape, local)])
}

impl BodyMass {
    /// Whether the step can divide by `x` (a mass or an inertia): a normal f32 whose inverse
    /// is normal too (not zero, subnormal or infinite).
    pub fn invertible(x: f32) -> bool {
        x.is_normal() && (1.0 / x).is_normal()
    }

    /// The mass data of shapes placed on a body by their local transforms, each with its
    /// density. For one shape at the origin this is exactly that shape's mass and inertia,
    /// bit for bit (every term added to it is zero).
    pub fn of_shapes<'a>(shapes: impl Iterator<Item = (&'a Shape, Transform, f32)>) -> BodyMass {
        let shapes: Vec<(&Shape, Transform, f32)> = shapes.collect();
        let mut mass = 0.0f32;
        let mut area = 0.0f32;
        let mut moment = Vec2::ZERO;
        let mut inertia = 0.0f32;
        let mut min_extent = f32::MAX;
        for &(shape, local, density) in &shapes {
            let md = shape.mass(density);
            // The shape's centre of mass in the body's frame (its origin but for a rounded
            // polygon's approximation; `local.apply(ZERO)` is `local.p` exactly).
            let c = if md.center == Vec2::ZERO {
                local.p
            } else {
                local.apply(md.center)
            };
            mass += md.mass;
            area += shape.mass(1.0).mass;
            moment += md.mass * c;
            // Parallel axis: each shape's inertia about the body's origin.
            inertia += md.inertia + md.mass * c.length_squared();
            if shape.has_area() {
                min_extent = min_extent.min(shape.min_extent());
            }
        }
        let center = if mass > 0.0 {
            moment / mass
        } else {
            Vec2::ZERO
        };
        // Back to the centre of mass (Box2D `b2UpdateBodyMassData`).
        inertia -= mass * center.length_squared();
        let extent = shapes.iter().fold(0.0f32, |e, (shape, local, _)| {
            e.max((local.p - center).length() + shape.extent())
        });
        BodyMass {
            mass,
            area,
            center,
            inertia,
            extent,
            min_extent: if min_extent == f32::MAX {
                0.0
            } else {
                min_extent
            },
        }
    }

    /// The mass data of a (validated) body definition's parts. Parts whose geometry is
    /// refused count nothing (validation refuses them first).
    pub fn of_def(def: &BodyDef) -> BodyMass {
        let parts: Vec<(Shape, Transform, f32)> = def
            .parts()
            .iter()
            .filter_map(|p| part_geometry(p).ok().map(|shapes| (shapes, p.density)))
            .flat_map(|(shapes, d)| shapes.into_iter().map(move |(s, l)| (s, l, d)))
            .collect();
        BodyMass::of_shapes(parts.iter().map(|(s, l, d)| (s, *l, *d)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::def::PartDef;

    #[test]
    fn one_shape_keeps_its_own_mass_and_inertia_bit_for_bit() {
        let def = BodyDef::new(ShapeDef::Box {
            half_extents: [0.7, 0.3],
            radius: 0.0,
        })
        .density(2.5);
        let shape = Shape::from_def(def.first_shape().unwrap()).unwrap();
        let own = shape.mass(2.5);
        let md = BodyMass::of_def(&def);
        assert_eq!(
            (md.mass, md.inertia, md.center),
            (own.mass, own.inertia, Vec2::ZERO)
        );
        assert_eq!(md.extent, shape.extent());
    }

    #[test]
    fn two_discs_follow_the_parallel_axis_theorem() {
        // Two unit-density discs of radius 0.5 at x = -1 and x = 3: centre x = 1, each
        // m = π/4, I = Σ (m r²/2 + m d²) with d = 2 (textbook; f32 sums, 1e-6 relative).
        let disc = || PartDef::new(ShapeDef::Circle { radius: 0.5 });
        let def = BodyDef::compound(vec![disc().at(-1.0, 0.0, 0.0), disc().at(3.0, 0.0, 0.0)]);
        let md = BodyMass::of_def(&def);
        let m = std::f32::consts::FRAC_PI_4;
        assert!((md.mass - 2.0 * m).abs() < 1e-6);
        assert!((md.center - Vec2::new(1.0, 0.0)).length() < 1e-6);
        let expected = 2.0 * (0.5 * m * 0.25 + m * 4.0);
        assert!((md.inertia / expected - 1.0).abs() < 1e-6, "{}", md.inertia);
        assert!((md.extent - 2.5).abs() < 1e-6);
    }

    #[test]
    fn a_part_polygon_keeps_its_place() {
        // A triangle given away from the part's origin: its centroid (1, 1/3) becomes the
        // part's offset, so the body's centre of mass is there.
        let tri = ShapeDef::Polygon {
            vertices: vec![[0.0, 0.0], [2.0, 0.0], [1.0, 1.0]],
            radius: 0.0,
        };
        let md = BodyMass::of_def(&BodyDef::compound(vec![PartDef::new(tri)]));
        assert!((md.center - Vec2::new(1.0, 1.0 / 3.0)).length() < 1e-6);
    }
}
