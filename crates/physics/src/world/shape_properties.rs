//! A shape's properties changed at run time (between steps), and what touches a body, a
//! shape or a sensor now. A material change reaches the shape's contacts at once; a density
//! change, its body's mass; a filter change, the pairs the broad phase finds.

use super::bodies::{invalid, non_negative};
use super::{ContactView, ShapeRecord, World, WorldError};
use crate::body::BodyMass;
use crate::def::{BodyKind, Filter};
use crate::id::{BodyId, JointId, ShapeId};

/// A shape's material, density, filter and tag, each with a setter and a getter (Box2D
/// v3's `b2Shape_Set…`); and the contacts that touch a body or a shape now, a sensor's
/// overlaps, a body's joints. A value the call cannot use is refused with
/// [`WorldError::Invalid`] naming the shape and the value, and changes nothing; a stale id
/// is [`WorldError::NoShape`] or [`WorldError::NoBody`].
///
/// ```
/// use tumble_physics::{BodyDef, BodyKind, Filter, ShapeDef, StepSettings, World};
///
/// let mut world = World::new(StepSettings::default());
/// let ground = world
///     .create_body(&BodyDef::new(ShapeDef::Box { half_extents: [5.0, 0.5], radius: 0.0 }).kind(BodyKind::Static))
///     .unwrap();
/// let ball = world.create_body(&BodyDef::new(ShapeDef::Circle { radius: 0.5 }).at(0.0, 1.0)).unwrap();
/// let ice = world.body_shapes(ground).unwrap().next().unwrap().id;
/// world.set_friction(ice, 0.02).unwrap();
/// assert!(world.set_friction(ice, -1.0).is_err());
/// // A conveyor's surface speed and a mat's rolling resistance, each with its getter.
/// world.set_tangent_speed(ice, 1.5).unwrap();
/// world.set_rolling_resistance(ice, 0.1).unwrap();
/// assert_eq!(world.rolling_resistance(ice), Ok(0.1));
/// world.step(1.0 / 60.0, 4);
/// assert_eq!(world.body_contacts(ball).unwrap().len(), 1);
/// // A filter that refuses the ground: the ball falls through it.
/// let shape = world.body_shapes(ball).unwrap().next().unwrap().id;
/// world.set_filter(shape, Filter { category: 2, mask: !1, group: 0 }).unwrap();
/// world.step(1.0 / 60.0, 4);
/// assert!(world.body_contacts(ball).unwrap().is_empty());
/// ```
impl World {
    /// Sets a shape's friction (≥ 0); its contacts mix it at once (the geometric mean).
    pub fn set_friction(&mut self, id: ShapeId, friction: f32) -> Result<(), WorldError> {
        let s = self.shape_slot(id)?;
        non_negative(id, "friction", friction)?;
        self.shapes.records[s].friction = friction;
        self.remix_contacts(s as u32);
        Ok(())
    }

    /// A shape's friction.
    pub fn friction(&self, id: ShapeId) -> Result<f32, WorldError> {
        self.shape_slot(id).map(|s| self.shapes.records[s].friction)
    }

    /// Sets a shape's restitution (≥ 0; 0 stops, 1 bounces back as fast); its contacts mix
    /// it at once (the larger of the two).
    pub fn set_restitution(&mut self, id: ShapeId, restitution: f32) -> Result<(), WorldError> {
        let s = self.shape_slot(id)?;
        non_negative(id, "restitution", restitution)?;
        self.shapes.records[s].restitution = restitution;
        self.remix_contacts(s as u32);
        Ok(())
    }

    /// A shape's restitution.
    pub fn restitution(&self, id: ShapeId) -> Result<f32, WorldError> {
        self.shape_slot(id)
            .map(|s| self.shapes.records[s].restitution)
    }

    /// Sets a shape's density (kg/m², ≥ 0); its body's mass, centre and inertia follow,
    /// computed again from its shapes (replacing any [`World::set_mass_data`]). Refused if
    /// it would leave a dynamic body without a mass f32 can invert.
    pub fn set_density(&mut self, id: ShapeId, density: f32) -> Result<(), WorldError> {
        let s = self.shape_slot(id)?;
        non_negative(id, "density", density)?;
        let body = self.shapes.records[s].body;
        let old = std::mem::replace(&mut self.shapes.records[s].density, density);
        if self.bodies.sims[body as usize].kind == BodyKind::Dynamic {
            let mass = self.shapes_mass(body as usize).mass;
            if !BodyMass::invertible(mass) {
                self.shapes.records[s].density = old;
                return Err(WorldError::Invalid {
                    what: format!("density {density} for {id}"),
                    why: format!(
                        "its body's mass would be {mass:e} kg, which f32 cannot invert: keep a shape with density"
                    ),
                });
            }
        }
        self.update_mass(body);
        self.debug_validate();
        Ok(())
    }

    /// A shape's density (kg/m²).
    pub fn density(&self, id: ShapeId) -> Result<f32, WorldError> {
        self.shape_slot(id).map(|s| self.shapes.records[s].density)
    }

    /// Sets a shape's collision filter. Its contacts end (what rested on it wakes) and its
    /// pairs are found again at the next step under the new filter, as Box2D's
    /// `b2Shape_SetFilter` does; a sensor's overlaps follow at the next step.
    pub fn set_filter(&mut self, id: ShapeId, filter: Filter) -> Result<(), WorldError> {
        let s = self.shape_slot(id)?;
        if self.shapes.records[s].filter == filter {
            return Ok(());
        }
        let body = self.shapes.records[s].body;
        self.shapes.records[s].filter = filter;
        self.wake_touching(&[body], |b| b == body);
        self.remove_contacts_where(|c| c.shape_a as usize == s || c.shape_b as usize == s);
        self.shapes.mark_moved(s as u32);
        self.debug_validate();
        Ok(())
    }

    /// A shape's collision filter.
    pub fn filter(&self, id: ShapeId) -> Result<Filter, WorldError> {
        self.shape_slot(id).map(|s| self.shapes.records[s].filter)
    }

    /// Sets how fast a shape's surface moves along itself (m/s, finite; positive: clockwise
    /// around the shape, rightwards along its top): a conveyor belt. Its contacts take it at
    /// once (summed with the other shape's, Box2D v3.1's rule); friction then drives what
    /// touches it to that speed. A contact whose shapes have none solves as before.
    pub fn set_tangent_speed(&mut self, id: ShapeId, speed: f32) -> Result<(), WorldError> {
        let s = self.shape_slot(id)?;
        if !speed.is_finite() {
            return Err(invalid(id, "tangent speed", speed, "it must be finite"));
        }
        self.shapes.records[s].tangent_speed = speed;
        // Prepare reads it from the shape at the next step.
        self.shapes.any_surface |= speed != 0.0;
        Ok(())
    }

    /// A shape's tangent speed (m/s).
    pub fn tangent_speed(&self, id: ShapeId) -> Result<f32, WorldError> {
        self.shape_slot(id)
            .map(|s| self.shapes.records[s].tangent_speed)
    }

    /// Sets how strongly a shape resists rolling (finite, ≥ 0; Box2D v3.1's
    /// `b2Shape_SetRollingResistance`): a contact brakes its two bodies' relative spin with
    /// a torque of at most the larger coefficient of its shapes times the larger shape
    /// radius times the normal force. Its contacts take it at once; 0 (the default) costs
    /// nothing in the step.
    pub fn set_rolling_resistance(
        &mut self,
        id: ShapeId,
        coefficient: f32,
    ) -> Result<(), WorldError> {
        let s = self.shape_slot(id)?;
        non_negative(id, "rolling resistance", coefficient)?;
        self.shapes.records[s].rolling_resistance = coefficient;
        self.shapes.any_surface |= coefficient > 0.0;
        Ok(())
    }

    /// A shape's rolling resistance coefficient.
    pub fn rolling_resistance(&self, id: ShapeId) -> Result<f32, WorldError> {
        self.shape_slot(id)
            .map(|s| self.shapes.records[s].rolling_resistance)
    }

    /// Tags a shape with a number of the caller's choosing (Box2D's `b2Shape_SetUserData`);
    /// a new shape carries 0, snapshots keep it, the step never reads it.
    pub fn set_shape_user_data(&mut self, id: ShapeId, user_data: u64) -> Result<(), WorldError> {
        let s = self.shape_slot(id)?;
        self.shapes.records[s].user_data = user_data;
        Ok(())
    }

    /// The tag [`World::set_shape_user_data`] gave a shape (0 if none).
    pub fn shape_user_data(&self, id: ShapeId) -> Result<u64, WorldError> {
        self.shape_slot(id)
            .map(|s| self.shapes.records[s].user_data)
    }

    /// The contacts of a body's shapes that touch now (their manifolds have points), in
    /// the solver's order: what it stands on, what presses on it. Sensors have none.
    pub fn body_contacts(&self, id: BodyId) -> Result<Vec<ContactView<'_>>, WorldError> {
        let i = self.slot(id)? as u32;
        Ok(self.touching_contacts(|c| c.body_a == i || c.body_b == i))
    }

    /// The contacts of a shape that touch now, in the solver's order.
    pub fn shape_contacts(&self, id: ShapeId) -> Result<Vec<ContactView<'_>>, WorldError> {
        let s = self.shape_slot(id)? as u32;
        Ok(self.touching_contacts(|c| c.shape_a == s || c.shape_b == s))
    }

    /// The shapes that overlapped a sensor at the end of the last step (or of the changes
    /// since), in slot order; refused for a shape that is not a sensor.
    pub fn sensor_overlaps(&self, id: ShapeId) -> Result<Vec<ShapeId>, WorldError> {
        let s = self.shape_slot(id)?;
        match self.sensors.get(&(s as u32)) {
            Some(overlaps) => Ok(overlaps.iter().map(|r| r.shape).collect()),
            None => Err(WorldError::Invalid {
                what: format!("{id}"),
                why: "it is not a sensor".into(),
            }),
        }
    }

    /// The joints that hold a body, in the order they were made.
    pub fn body_joints(&self, id: BodyId) -> Result<Vec<JointId>, WorldError> {
        let i = self.slot(id)? as u32;
        Ok(self
            .joint_ids()
            .filter(|&j| {
                self.joint_bodies(j)
                    .is_ok_and(|[a, b]| a.index == i || b.index == i)
            })
            .collect())
    }

    /// The touching contacts `which` picks, as views.
    fn touching_contacts(&self, which: impl Fn(&super::Contact) -> bool) -> Vec<ContactView<'_>> {
        self.contacts
            .list
            .iter()
            .filter(|c| c.manifold.count > 0 && which(c))
            .map(|c| self.contact_view(c))
            .collect()
    }

    /// Mixes shape `s`'s material into its contacts again.
    fn remix_contacts(&mut self, s: u32) {
        let records = &self.shapes.records;
        for c in &mut self.contacts.list {
            if c.shape_a == s || c.shape_b == s {
                let (a, b) = (&records[c.shape_a as usize], &records[c.shape_b as usize]);
                c.friction = ShapeRecord::mixed_friction(a, b);
                c.restitution = ShapeRecord::mixed_restitution(a, b);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec2;

    use super::*;
    use crate::def::{BodyDef, PartDef, ShapeDef};
    use crate::joint::JointDef;
    use crate::world::StepSettings;

    const DT: f32 = 1.0 / 60.0;

    /// A static ground along y = 0 and a unit box resting on it, its shape.
    fn box_on_ground() -> (World, BodyId, ShapeId, ShapeId) {
        let mut w = World::new(StepSettings::default());
        let g = w
            .create_body(
                &BodyDef::new(ShapeDef::Box {
                    half_extents: [50.0, 0.5],
                    radius: 0.0,
                })
                .kind(BodyKind::Static)
                .at(0.0, -0.5),
            )
            .unwrap();
        let b = w
            .create_body(
                &BodyDef::new(ShapeDef::Box {
                    half_extents: [0.5, 0.5],
                    radius: 0.0,
                })
                .at(0.0, 0.5),
            )
            .unwrap();
        let first = |w: &World, b| w.body_shapes(b).unwrap().next().unwrap().id;
        let (sg, sb) = (first(&w, g), first(&w, b));
        (w, b, sb, sg)
    }

    #[test]
    fn friction_set_to_zero_lets_a_touching_box_slide_on_at_its_speed() {
        let (mut w, b, sb, sg) = box_on_ground();
        for _ in 0..10 {
            w.step(DT, 4);
        }
        assert_eq!(w.shape_contacts(sg).unwrap().len(), 1);
        w.set_velocity(b, Vec2::new(2.0, 0.0), 0.0).unwrap();
        // The contact exists already: it takes the new mix at once (sqrt(0 · 0.6) = 0).
        w.set_friction(sb, 0.0).unwrap();
        assert!(w.set_friction(sb, -0.1).is_err() && w.set_friction(sb, f32::NAN).is_err());
        assert_eq!(w.friction(sb), Ok(0.0));
        for _ in 0..60 {
            w.step(DT, 4);
        }
        // Frictionless, nothing slows it but the solver's contact noise (measured: 1.7e-4
        // m/s in 60 steps; with the ground's 0.6 and the box's 0.6 it stops within 0.4 s).
        let vx = w.body(b).unwrap().linear_velocity.x;
        assert!((vx - 2.0).abs() < 1e-3, "{vx}");
        // With friction back it stops within the second.
        w.set_friction(sb, 0.6).unwrap();
        for _ in 0..60 {
            w.step(DT, 4);
        }
        assert!(w.body(b).unwrap().linear_velocity.x.abs() < 1e-3);
    }

    #[test]
    fn restitution_set_at_run_time_bounces_and_density_moves_the_mass() {
        let (mut w, b, sb, sg) = box_on_ground();
        w.set_restitution(sg, 1.0).unwrap();
        assert!(w.set_restitution(sg, -1.0).is_err());
        assert_eq!(w.restitution(sg), Ok(1.0));
        w.set_transform(b, Vec2::new(0.0, 3.0), 0.0).unwrap();
        let mut top = 0.0f32;
        let mut fell = false;
        for _ in 0..150 {
            w.step(DT, 4);
            let y = w.body(b).unwrap().position.y;
            fell |= y < 1.0;
            if fell {
                top = top.max(y);
            }
        }
        // Dropped from 3 m, it bounces back above 2 m (measured: 2.41; without restitution
        // it stays at 0.5, on the ground).
        assert!(top > 2.0, "{top}");
        w.set_density(sb, 3.0).unwrap();
        assert_eq!(w.mass(b), Ok(3.0));
        assert_eq!(w.density(sb), Ok(3.0));
        // The only shape with mass cannot lose it; the refusal changes nothing.
        assert!(w.set_density(sb, 0.0).is_err());
        assert!(w.set_density(sb, f32::NAN).is_err());
        assert_eq!((w.mass(b), w.density(sb)), (Ok(3.0), Ok(3.0)));
        w.validate().unwrap();
    }

    #[test]
    fn a_filter_set_at_run_time_drops_the_box_through_the_ground_and_back_onto_it() {
        let (mut w, b, sb, _) = box_on_ground();
        for _ in 0..10 {
            w.step(DT, 4);
        }
        assert_eq!(w.body_contacts(b).unwrap().len(), 1);
        let ghost = Filter {
            category: 2,
            mask: !1,
            group: 0,
        };
        w.set_filter(sb, ghost).unwrap();
        assert_eq!(w.filter(sb), Ok(ghost));
        for _ in 0..45 {
            w.step(DT, 4);
        }
        assert!(w.body_contacts(b).unwrap().is_empty());
        // Free fall for 0.75 s: 2.8 m.
        let y = w.body(b).unwrap().position.y;
        assert!(y < -2.0, "{y}");
        // Lifted back above it with the default filter, it lands and rests on it again.
        w.set_filter(sb, Filter::default()).unwrap();
        w.set_transform(b, Vec2::new(0.0, 2.0), 0.0).unwrap();
        w.set_velocity(b, Vec2::ZERO, 0.0).unwrap();
        for _ in 0..90 {
            w.step(DT, 4);
        }
        assert_eq!(w.body_contacts(b).unwrap().len(), 1);
        assert!((w.body(b).unwrap().position.y - 0.5).abs() < 0.02);
    }

    #[test]
    fn sensors_list_their_overlaps_joints_their_bodies_and_shapes_keep_their_tags() {
        let (mut w, b, sb, sg) = box_on_ground();
        let sensor = w
            .create_body(
                &BodyDef::compound(vec![
                    PartDef::new(ShapeDef::Circle { radius: 2.0 }).sensor(true),
                ])
                .kind(BodyKind::Static)
                .at(0.0, 1.0),
            )
            .unwrap();
        let zone = w.body_shapes(sensor).unwrap().next().unwrap().id;
        w.step(DT, 4);
        // The box and the ground both reach into the zone: in slot order.
        assert_eq!(w.sensor_overlaps(zone), Ok(vec![sg, sb]));
        assert!(matches!(
            w.sensor_overlaps(sb),
            Err(WorldError::Invalid { .. })
        ));
        let ground = w.shape(sg).unwrap().body;
        let j = w
            .create_joint(&JointDef::hinge([ground, b], [0.0, 0.0]))
            .unwrap();
        assert_eq!(w.body_joints(b), Ok(vec![j]));
        assert_eq!(w.body_joints(sensor), Ok(vec![]));
        w.set_shape_user_data(sb, 42).unwrap();
        let copy = World::from_snapshot(w.snapshot()).unwrap();
        assert_eq!(copy.shape_user_data(sb), Ok(42));
        assert_eq!(copy.shape_user_data(sg), Ok(0));
    }

    #[test]
    fn a_conveyor_carries_boxes_at_its_speed_alike_in_scalar_and_simd() {
        // A static belt 40 m long with 20 boxes on it (enough for full 8-lane constraints);
        // the belt's top moves at 2 m/s to the right.
        let run = |simd: bool, avx: bool| {
            let mut w = World::new(StepSettings::default());
            w.settings_mut().simd = simd;
            w.solver.use_avx = avx;
            let belt = w
                .create_body(
                    &BodyDef::compound(vec![
                        PartDef::new(ShapeDef::Box {
                            half_extents: [20.0, 0.5],
                            radius: 0.0,
                        })
                        .tangent_speed(2.0),
                    ])
                    .kind(BodyKind::Static)
                    .at(0.0, -0.5),
                )
                .unwrap();
            let boxes: Vec<BodyId> = (0..20)
                .map(|k| {
                    w.create_body(
                        &BodyDef::new(ShapeDef::Box {
                            half_extents: [0.4, 0.4],
                            radius: 0.0,
                        })
                        .at(-15.0 + 1.2 * k as f32, 0.4),
                    )
                    .unwrap()
                })
                .collect();
            let surface = w.body_shapes(belt).unwrap().next().unwrap().id;
            assert_eq!(w.tangent_speed(surface), Ok(2.0));
            for _ in 0..120 {
                w.step(DT, 4);
            }
            // Carried at the belt's speed (1e-3 m/s: the solver's contact noise; friction
            // 0.6 brings them there within 0.35 s).
            for &b in &boxes {
                let v = w.body(b).unwrap().linear_velocity;
                assert!((v.x - 2.0).abs() < 1e-3 && v.y.abs() < 1e-3, "{v}");
            }
            // Stopped, the belt holds them still.
            w.set_tangent_speed(surface, 0.0).unwrap();
            assert!(w.set_tangent_speed(surface, f32::NAN).is_err());
            for _ in 0..60 {
                w.step(DT, 4);
            }
            for &b in &boxes {
                assert!(w.body(b).unwrap().linear_velocity.x.abs() < 1e-3);
            }
            w.state_hash()
        };
        let portable = run(true, false);
        assert_eq!(run(true, true), portable);
        assert_eq!(run(false, false), portable);
    }

    #[test]
    fn a_part_with_a_tangent_speed_loads_from_a_scene_file_and_a_bad_one_is_refused() {
        let json = r#"{"name": "belt", "bodies": [{"kind": "Static", "shapes": [
            {"shape": {"Box": {"half_extents": [5, 0.5]}}, "tangent_speed": -1.5}]}]}"#;
        let scene: crate::SceneDef = serde_json::from_str(json).unwrap();
        let w = World::from_scene(&scene, &crate::Limits::default()).unwrap();
        let belt = w.shapes().next().unwrap().id;
        assert_eq!(w.tangent_speed(belt), Ok(-1.5));
        let mut bad = BodyDef::compound(vec![
            PartDef::new(ShapeDef::Circle { radius: 1.0 }).tangent_speed(f32::INFINITY),
        ]);
        bad = bad.kind(BodyKind::Static);
        let err = World::new(StepSettings::default())
            .create_body(&bad)
            .unwrap_err()
            .to_string();
        assert!(err.contains("tangent_speed"), "{err}");
    }

    /// A static floor 300 m long and `n` balls of radius 0.5, 12 m apart (none reaches the
    /// next in 4 s), rolling on it at 2 m/s (spin matched, so they roll without slipping),
    /// every other one with rolling resistance `coefficient` on its shape when `mixed`, else
    /// all of them.
    fn rolling_balls(n: usize, coefficient: f32, mixed: bool) -> (World, Vec<BodyId>) {
        let mut w = World::new(StepSettings::default());
        w.create_body(
            &BodyDef::new(ShapeDef::Box {
                half_extents: [150.0, 0.5],
                radius: 0.0,
            })
            .kind(BodyKind::Static)
            .at(0.0, -0.5),
        )
        .unwrap();
        let balls = (0..n)
            .map(|k| {
                let resists = !mixed || k % 2 == 0;
                let part = PartDef::new(ShapeDef::Circle { radius: 0.5 })
                    .rolling_resistance(if resists { coefficient } else { 0.0 });
                w.create_body(
                    &BodyDef::compound(vec![part])
                        .at(-145.0 + 12.0 * k as f32, 0.5)
                        .velocity(2.0, 0.0)
                        .spin(-4.0),
                )
                .unwrap()
            })
            .collect();
        (w, balls)
    }

    #[test]
    fn a_ball_on_rolling_resistance_stops_where_the_energy_balance_says() {
        // Rolling without slipping, the resistance's torque c·r·N = c·r·m·g brakes the
        // energy ½(m + I/r²)v² = ¾mv² (a disc: I = ½mr²) at c·r·m·g·v/r, so v falls at
        // (2/3)·c·g: from 2 m/s with c = 0.1, g = 10 it stops in 3 s after 3 m.
        let (mut w, balls) = rolling_balls(1, 0.1, false);
        let ball = balls[0];
        let shape = w.body_shapes(ball).unwrap().next().unwrap().id;
        assert_eq!(w.rolling_resistance(shape), Ok(0.1));
        let x0 = w.body(ball).unwrap().position.x;
        let mut stopped_at = None;
        for k in 1..=300 {
            w.step(DT, 4);
            let v = w.body(ball).unwrap().linear_velocity.x;
            if k == 90 {
                // Halfway in time: half the speed (1 m/s), as a constant deceleration has it.
                // 2% for the soft contact's give at touchdown and the discrete steps.
                assert!((v - 1.0).abs() < 0.02, "{v} m/s at 1.5 s");
            }
            if stopped_at.is_none() && v.abs() < 1e-3 {
                stopped_at = Some(k);
            }
        }
        let travelled = w.body(ball).unwrap().position.x - x0;
        // 3 m and 3 s within 2% (the same sources as above); once stopped it stays (the
        // resistance holds it like static friction, as Box2D's clamp does).
        assert!((travelled - 3.0).abs() < 0.06, "{travelled} m");
        let t = stopped_at.expect("it stops") as f32 * DT;
        assert!((t - 3.0).abs() < 0.06, "{t} s");
        assert!(w.body(ball).unwrap().linear_velocity.length() < 1e-3);

        // Without it, the ball rolls on at 2 m/s (5e-3: the contact's noise over 5 s).
        w.set_rolling_resistance(shape, 0.0).unwrap();
        w.set_velocity(ball, Vec2::new(2.0, 0.0), -4.0).unwrap();
        for _ in 0..300 {
            w.step(DT, 4);
        }
        let v = w.body(ball).unwrap().linear_velocity.x;
        assert!((v - 2.0).abs() < 5e-3, "{v}");
        assert!(w.set_rolling_resistance(shape, -0.1).is_err());
        assert!(w.set_rolling_resistance(shape, f32::NAN).is_err());
        assert_eq!(w.rolling_resistance(shape), Ok(0.0));
    }

    #[test]
    fn rolling_resistance_is_alike_in_scalar_portable_simd_and_avx2_with_lanes_mixed() {
        // 24 balls (three full 8-lane constraints), every other one resisting, so wide
        // constraints mix lanes with and without it.
        let run = |simd: bool, avx: bool| {
            let (mut w, balls) = rolling_balls(24, 0.2, true);
            w.settings_mut().simd = simd;
            w.solver.use_avx = avx;
            for _ in 0..240 {
                w.step(DT, 4);
            }
            // Those resisting stopped (2 m/s at (2/3)·0.2·10 stops within 1.5 s); the others
            // roll on.
            for (k, &b) in balls.iter().enumerate() {
                let v = w.body(b).unwrap().linear_velocity.x;
                if k % 2 == 0 {
                    assert!(v.abs() < 1e-3, "ball {k}: {v}");
                } else {
                    assert!((v - 2.0).abs() < 5e-3, "ball {k}: {v}");
                }
            }
            w.state_hash()
        };
        let portable = run(true, false);
        assert_eq!(run(true, true), portable);
        assert_eq!(run(false, false), portable);
    }

    #[test]
    fn rolling_resistance_loads_from_a_scene_file_and_a_bad_one_is_refused() {
        let json = r#"{"name": "mat", "bodies": [{"kind": "Static", "shapes": [
            {"shape": {"Circle": {"radius": 0.5}}, "rolling_resistance": 0.3}]}]}"#;
        let scene: crate::SceneDef = serde_json::from_str(json).unwrap();
        let w = World::from_scene(&scene, &crate::Limits::default()).unwrap();
        let mat = w.shapes().next().unwrap().id;
        assert_eq!(w.rolling_resistance(mat), Ok(0.3));
        let bad = BodyDef::compound(vec![
            PartDef::new(ShapeDef::Circle { radius: 1.0 }).rolling_resistance(-1.0),
        ]);
        let err = World::new(StepSettings::default())
            .create_body(&bad)
            .unwrap_err()
            .to_string();
        assert!(err.contains("rolling_resistance"), "{err}");
    }
}
