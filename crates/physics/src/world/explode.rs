//! Explosions: Box2D v3.1's `b2World_Explode` (`src/world.c`, `ExplodeCallback`), an
//! impulse on every dynamic shape near a point, in proportion to the outline it turns to the
//! blast.

use glam::Vec2;

use super::query::QueryFilter;
use super::{World, WorldError};
use crate::collision::distance::{Proxy, distance};
use crate::def::BodyKind;
use crate::math::{Transform, cross};
use crate::shape::Aabb;

/// A blast ([`World::explode`]), as Box2D's `b2ExplosionDef`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ExplosionDef {
    /// Its centre (m, world).
    pub position: Vec2,
    /// Within this distance of the centre (m, ≥ 0) a shape takes the full impulse.
    pub radius: f32,
    /// Beyond `radius` the impulse falls linearly to 0 over this distance (m, ≥ 0).
    pub falloff: f32,
    /// Impulse (N·s) per metre of outline facing the blast; negative pulls inwards.
    pub impulse_per_length: f32,
    /// The categories of shapes it reaches (a shape's filter `category` must meet it).
    pub mask: u64,
}

impl Default for ExplosionDef {
    /// At the origin, radius 1, no falloff, 1 N·s per metre, every category.
    fn default() -> Self {
        ExplosionDef {
            position: Vec2::ZERO,
            radius: 1.0,
            falloff: 0.0,
            impulse_per_length: 1.0,
            mask: u64::MAX,
        }
    }
}

/// Explosions.
///
/// ```
/// use tumble_physics::{BodyDef, ExplosionDef, ShapeDef, StepSettings, Vec2, World};
///
/// let mut world = World::new(StepSettings { gravity: Vec2::ZERO, ..StepSettings::default() });
/// let crate_ = world
///     .create_body(&BodyDef::new(ShapeDef::Box { half_extents: [0.5, 0.5], radius: 0.0 }).at(2.0, 0.0))
///     .unwrap();
/// world.explode(&ExplosionDef { radius: 3.0, impulse_per_length: 2.0, ..ExplosionDef::default() }).unwrap();
/// // The crate's 1 m face turned to the blast takes 2 N·s: 2 m/s for its 1 kg, away from it.
/// assert!((world.body(crate_).unwrap().linear_velocity - Vec2::new(2.0, 0.0)).length() < 1e-5);
/// ```
impl World {
    /// Pushes every dynamic body's shapes within `radius + falloff` of the blast away from
    /// it (between steps), waking them: each shape takes `impulse_per_length` times the
    /// length of its outline projected across the direction from the blast to its closest
    /// point, at that point, full within `radius` and falling linearly to 0 at
    /// `radius + falloff`. Shapes are taken in slot order, so the result is the same on any
    /// thread count. Sensors are not pushed (Box2D's queries them too; they have no
    /// surface to push). A non-finite or negative size is refused, the world unchanged.
    pub fn explode(&mut self, def: &ExplosionDef) -> Result<(), WorldError> {
        let ExplosionDef {
            position,
            radius,
            falloff,
            impulse_per_length,
            mask,
        } = *def;
        let bad = |what: &str, why: &str| {
            Err(WorldError::Invalid {
                what: format!("explosion {what}"),
                why: why.into(),
            })
        };
        if !position.is_finite() {
            return bad(&format!("position {position:?}"), "it must be finite");
        }
        for (what, v) in [("radius", radius), ("falloff", falloff)] {
            if !(v.is_finite() && v >= 0.0) {
                return bad(&format!("{what} {v}"), "it must be finite and >= 0");
            }
        }
        if !impulse_per_length.is_finite() {
            return bad(
                &format!("impulse_per_length {impulse_per_length}"),
                "it must be finite",
            );
        }
        let reach = radius + falloff;
        let aabb = Aabb {
            min: position - Vec2::splat(reach),
            max: position + Vec2::splat(reach),
        };
        // Box2D's query tests the mask against the shape's category alone.
        let filter = QueryFilter {
            category: u64::MAX,
            mask,
            sensors: false,
            exclude_body: None,
        };
        let mut near = Vec::new();
        self.shapes_in_box(&aabb, &filter, |s| {
            let body = self.shapes.records[s as usize].body as usize;
            if self.bodies.sims[body].kind == BodyKind::Dynamic {
                near.push(s);
            }
            true
        });
        near.sort_unstable();
        let blast = Proxy::points(&[position], 0.0, Transform::IDENTITY);
        for s in near {
            let pose = self.shape_pose(s);
            let shape = Proxy::of(&self.shapes.geometry[s as usize], pose);
            let closest = distance(&shape, Transform::IDENTITY, &blast, Transform::IDENTITY);
            // Distances from the shape's surface (its core rounded by its radius).
            let gap = (closest.distance - shape.radius).max(0.0);
            if gap > reach {
                continue;
            }
            let body = self.shapes.records[s as usize].body;
            self.wake_body(body);
            let point = if gap > 0.0 {
                closest.point_a
                    + (closest.point_b - closest.point_a) * (shape.radius / closest.distance)
            } else {
                // The blast is inside the shape: push from its centroid (the shape's own
                // origin for a shape with area, a segment's middle).
                let core = shape.core();
                core.iter().copied().sum::<Vec2>() / core.len() as f32
            };
            let away = point - position;
            let direction = if away.length_squared() > 100.0 * f32::EPSILON * f32::EPSILON {
                away.normalize()
            } else {
                Vec2::X
            };
            // The outline's extent across the direction (Box2D's
            // `b2GetShapeProjectedPerimeter`): the core's spread along the perpendicular,
            // plus the rounding on both sides.
            let across = Vec2::new(-direction.y, direction.x);
            let (lo, hi) = shape
                .core()
                .iter()
                .map(|&p| p.dot(across))
                .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), d| {
                    (lo.min(d), hi.max(d))
                });
            let perimeter = (hi - lo) + 2.0 * shape.radius;
            let scale = if gap > radius && falloff > 0.0 {
                ((reach - gap) / falloff).clamp(0.0, 1.0)
            } else {
                1.0
            };
            let impulse = direction * (impulse_per_length * perimeter * scale);
            let i = body as usize;
            let m = self.bodies.masses[i];
            let center = self.bodies.sims[i].xf.p;
            let st = &mut self.bodies.states[i];
            st.v += impulse * m.inv_mass;
            st.w += m.inv_inertia * cross(point - center, impulse);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::def::{BodyDef, ShapeDef};
    use crate::world::StepSettings;

    fn unit_box_at(w: &mut World, x: f32, y: f32) -> crate::BodyId {
        w.create_body(
            &BodyDef::new(ShapeDef::Box {
                half_extents: [0.5, 0.5],
                radius: 0.0,
            })
            .at(x, y),
        )
        .unwrap()
    }

    #[test]
    fn a_blast_pushes_by_the_outline_it_faces_falls_off_and_wakes_the_sleeping() {
        let mut w = World::new(StepSettings {
            gravity: Vec2::ZERO,
            ..StepSettings::default()
        });
        // Within the radius, at 1.5 m beyond it (half the falloff), past the reach, and a
        // diagonal one (its corner faces the blast: √2 m of outline across).
        let near = unit_box_at(&mut w, 2.0, 0.0);
        let half = unit_box_at(&mut w, 0.0, -4.5);
        let far = unit_box_at(&mut w, -8.0, 0.0);
        let diagonal = unit_box_at(&mut w, 2.0, 2.0);
        w.set_awake(half, false).unwrap();
        let def = ExplosionDef {
            radius: 2.5,
            falloff: 3.0,
            impulse_per_length: 2.0,
            ..ExplosionDef::default()
        };
        w.explode(&def).unwrap();
        let v = |b| w.body(b).unwrap().linear_velocity;
        // 1 m of face at 1.5 m from the blast: 2 N·s on 1 kg (1e-5: f32).
        assert!(
            (v(near) - Vec2::new(2.0, 0.0)).length() < 1e-5,
            "{}",
            v(near)
        );
        // Its face 4 m away: 1.5 m into the 3 m falloff, half the impulse; it woke.
        assert!(
            (v(half) - Vec2::new(0.0, -1.0)).length() < 1e-5,
            "{}",
            v(half)
        );
        assert_eq!(w.is_awake(half), Ok(true));
        assert_eq!(v(far), Vec2::ZERO);
        // The corner (1.5, 1.5) is closest: pushed along the diagonal by 2·√2 N·s, through
        // its centre, so it does not turn.
        let d = v(diagonal);
        assert!((d - Vec2::splat(2.0)).length() < 1e-4, "{d}");
        assert!(w.body(diagonal).unwrap().angular_velocity.abs() < 1e-5);
        // A mask that misses the default category reaches nothing; bad sizes are refused.
        let before = w.state_hash();
        w.explode(&ExplosionDef { mask: 2, ..def }).unwrap();
        assert_eq!(w.state_hash(), before);
        for bad in [
            ExplosionDef {
                radius: -1.0,
                ..def
            },
            ExplosionDef {
                falloff: f32::NAN,
                ..def
            },
            ExplosionDef {
                impulse_per_length: f32::INFINITY,
                ..def
            },
            ExplosionDef {
                position: Vec2::new(f32::NAN, 0.0),
                ..def
            },
        ] {
            assert!(matches!(w.explode(&bad), Err(WorldError::Invalid { .. })));
        }
        assert_eq!(w.state_hash(), before);
    }
}
