//! A body's properties changed at run time (between steps): damping, gravity scale, fixed
//! rotation, sleep, mass data; each checked, each keeping every copy the step reads in
//! agreement (the motion flags, the solver's masses, the contacts' copies of them).

use super::bodies::{finite, invalid, non_negative};
use super::{World, WorldError};
use crate::body::BodyMass;
use crate::def::BodyKind;
use crate::id::BodyId;
use crate::shape::MassData;

/// A body's properties, each with a setter and a getter: what Box2D v3's `b2Body_Set…`
/// calls change. A value the call cannot use is refused with [`WorldError::Invalid`] naming
/// the body and the value, and changes nothing; a stale id is [`WorldError::NoBody`].
///
/// ```
/// use tumble_physics::{BodyDef, MassData, ShapeDef, StepSettings, Vec2, World};
///
/// let mut world = World::new(StepSettings::default());
/// let balloon = world.create_body(&BodyDef::new(ShapeDef::Circle { radius: 0.5 })).unwrap();
/// world.set_gravity_scale(balloon, -0.2).unwrap();
/// world.set_linear_damping(balloon, 0.5).unwrap();
/// assert!(world.set_linear_damping(balloon, -1.0).is_err());
/// world.set_mass_data(balloon, MassData { mass: 2.0, center: Vec2::ZERO, inertia: 0.25 }).unwrap();
/// world.step(1.0 / 60.0, 4);
/// assert!(world.body(balloon).unwrap().linear_velocity.y > 0.0);
/// assert_eq!(world.mass_data(balloon).unwrap().mass, 2.0);
/// // Disabled, it stays where it is, seen by nothing, until enabled again.
/// let at = world.body(balloon).unwrap().position;
/// world.set_enabled(balloon, false).unwrap();
/// world.step(1.0 / 60.0, 4);
/// assert_eq!(world.body(balloon).unwrap().position, at);
/// assert_eq!(world.body_at(at), None);
/// world.set_enabled(balloon, true).unwrap();
/// assert_eq!(world.body_at(at), Some(balloon));
/// ```
impl World {
    /// Sets a body's linear damping (per second, ≥ 0): its speed decays as `1/(1 + h·c)`
    /// per substep of `h`.
    pub fn set_linear_damping(&mut self, id: BodyId, damping: f32) -> Result<(), WorldError> {
        let i = self.slot(id)?;
        non_negative(id, "linear damping", damping)?;
        self.bodies.records[i].linear_damping = damping;
        self.bodies.refresh_motion(i as u32);
        Ok(())
    }

    /// A body's linear damping (per second).
    pub fn linear_damping(&self, id: BodyId) -> Result<f32, WorldError> {
        self.slot(id).map(|i| self.bodies.records[i].linear_damping)
    }

    /// Sets a body's angular damping (per second, ≥ 0).
    pub fn set_angular_damping(&mut self, id: BodyId, damping: f32) -> Result<(), WorldError> {
        let i = self.slot(id)?;
        non_negative(id, "angular damping", damping)?;
        self.bodies.records[i].angular_damping = damping;
        self.bodies.refresh_motion(i as u32);
        Ok(())
    }

    /// A body's angular damping (per second).
    pub fn angular_damping(&self, id: BodyId) -> Result<f32, WorldError> {
        self.slot(id)
            .map(|i| self.bodies.records[i].angular_damping)
    }

    /// Sets how much of the world's gravity acts on a body (any finite number: 0 floats,
    /// negative rises). A sleeping body keeps sleeping until something wakes it (Box2D's
    /// rule); wake it with [`World::set_awake`] if it should respond at once.
    pub fn set_gravity_scale(&mut self, id: BodyId, scale: f32) -> Result<(), WorldError> {
        let i = self.slot(id)?;
        if !scale.is_finite() {
            return Err(invalid(id, "gravity scale", scale, "it must be finite"));
        }
        self.bodies.records[i].gravity_scale = scale;
        self.bodies.refresh_motion(i as u32);
        Ok(())
    }

    /// A body's gravity scale.
    pub fn gravity_scale(&self, id: BodyId) -> Result<f32, WorldError> {
        self.slot(id).map(|i| self.bodies.records[i].gravity_scale)
    }

    /// Keeps a body from turning (its inverse inertia becomes 0 and its spin stops) or lets
    /// it turn again. Its mass data are computed again from its shapes, replacing any
    /// [`World::set_mass_data`] (as Box2D's `b2Body_SetFixedRotation` does).
    pub fn set_fixed_rotation(&mut self, id: BodyId, fixed: bool) -> Result<(), WorldError> {
        let i = self.slot(id)?;
        if self.bodies.records[i].fixed_rotation == fixed {
            return Ok(());
        }
        self.bodies.records[i].fixed_rotation = fixed;
        self.bodies.states[i].w = 0.0;
        self.update_mass(i as u32);
        self.debug_validate();
        Ok(())
    }

    /// Whether a body is kept from turning.
    pub fn fixed_rotation(&self, id: BodyId) -> Result<bool, WorldError> {
        self.slot(id).map(|i| self.bodies.records[i].fixed_rotation)
    }

    /// Lets a body sleep or not; a body that may not sleep keeps its island awake.
    /// Disabling sleep wakes it (Box2D's `b2Body_EnableSleep`).
    pub fn set_sleep_enabled(&mut self, id: BodyId, enabled: bool) -> Result<(), WorldError> {
        let i = self.slot(id)?;
        self.bodies.records[i].enable_sleep = enabled;
        if !enabled {
            self.wake_body(i as u32);
        }
        Ok(())
    }

    /// Whether a body may sleep.
    pub fn sleep_enabled(&self, id: BodyId) -> Result<bool, WorldError> {
        self.slot(id).map(|i| self.bodies.records[i].enable_sleep)
    }

    /// Wakes a body's island, or puts it to sleep now (its bodies stopped). Only dynamic
    /// bodies sleep: for a static or kinematic body this does nothing.
    pub fn set_awake(&mut self, id: BodyId, awake: bool) -> Result<(), WorldError> {
        let i = self.slot(id)?;
        if self.bodies.sims[i].kind != BodyKind::Dynamic {
            return Ok(());
        }
        if awake {
            self.wake_body(i as u32);
        } else {
            self.sleep_island_of(i as u32);
        }
        self.debug_validate();
        Ok(())
    }

    /// Takes a body out of the world (`false`) or puts it back (`true`), between steps
    /// (Box2D's `b2Body_Disable` / `b2Body_Enable`). A disabled body touches nothing: its
    /// contacts end (with contact end events, and what rested on it wakes), its shapes leave
    /// the broad phase, so no pair, query, sensor, explosion or [`World::draw`] sees them,
    /// it is not integrated or solved, and its joints are kept but not solved. It keeps its
    /// shapes, joints, pose and velocity, and comes back where it was left (or where
    /// [`World::set_transform`] put it meanwhile), awake, its joints joining islands again.
    /// Impulses and forces given while it is disabled are ignored, as sleeping bodies'
    /// are without `wake`.
    pub fn set_enabled(&mut self, id: BodyId, enabled: bool) -> Result<(), WorldError> {
        let i = self.slot(id)?;
        if self.bodies.records[i].disabled != enabled {
            return Ok(());
        }
        let body = i as u32;
        if enabled {
            self.bodies.records[i].disabled = false;
            for s in self.shapes_of_body(i).collect::<Vec<_>>() {
                self.shapes.set_disabled(s, false);
            }
            let kind = self.bodies.sims[i].kind;
            self.bodies.awake[i] = kind != BodyKind::Static;
            self.bodies.sims[i].sleep_time = 0.0;
            if kind == BodyKind::Dynamic {
                self.islands.create(body, true);
            }
            self.bodies.refresh_motion(body);
            // Its joints join islands again; a sleeping island joined wakes first, as a new
            // joint's does.
            let joined: Vec<u32> = self.joints_of_body(body).collect();
            for k in joined {
                let j = &self.joints.list[k as usize];
                let (a, b) = (j.body_a, j.body_b);
                if j.links_islands() && self.links_islands_of(a, b) {
                    self.wake_body(a);
                    self.wake_body(b);
                    self.islands.link(a, b);
                }
            }
            self.refresh_contact_keys();
            // Its shapes look for pairs at the next step.
            self.refresh_shape_boxes(body);
        } else {
            self.wake_touching(&[body], |b| b == body);
            self.remove_contacts_of(body);
            self.islands.remove_body(body);
            self.bodies.records[i].disabled = true;
            for s in self.shapes_of_body(i).collect::<Vec<_>>() {
                self.shapes.set_disabled(s, true);
            }
            self.bodies.awake[i] = false;
            self.bodies.refresh_motion(body);
        }
        // Which joints are solved changed.
        self.edit_joints();
        self.debug_validate();
        Ok(())
    }

    /// Whether a body is enabled ([`World::set_enabled`]).
    pub fn is_enabled(&self, id: BodyId) -> Result<bool, WorldError> {
        self.slot(id).map(|i| !self.bodies.records[i].disabled)
    }

    /// Gives a dynamic body its mass, centre of mass (in its frame) and rotational inertia
    /// about that centre, in place of its shapes' (Box2D's `b2Body_SetMassData`). They hold
    /// until its shapes, their densities, its kind or its fixed rotation change, which
    /// compute them again from the shapes. The body's frame stays where it is; its centre moves with the data.
    pub fn set_mass_data(&mut self, id: BodyId, data: MassData) -> Result<(), WorldError> {
        let i = self.slot(id)?;
        if self.bodies.sims[i].kind != BodyKind::Dynamic {
            return Err(WorldError::Invalid {
                what: format!("mass data for {id}"),
                why: "only a dynamic body has mass; make it dynamic first".into(),
            });
        }
        if !(data.mass > 0.0 && BodyMass::invertible(data.mass)) {
            return Err(invalid(
                id,
                "mass",
                data.mass,
                "it must be > 0 and invertible in f32",
            ));
        }
        finite("centre of mass", data.center)?;
        let inertia = data.inertia;
        if !(inertia == 0.0 || (inertia > 0.0 && BodyMass::invertible(inertia))) {
            return Err(invalid(
                id,
                "rotational inertia",
                inertia,
                "it must be 0 (no turning) or > 0 and invertible in f32",
            ));
        }
        let min_extent = self.bodies.sims[i].min_extent;
        self.bodies.records[i].custom_mass = true;
        self.apply_mass(i as u32, data.mass, data.center, inertia, min_extent);
        self.refresh_contact_masses(i as u32);
        self.debug_validate();
        Ok(())
    }

    /// A body's mass, centre of mass (in its frame) and rotational inertia about it; zeros
    /// for a static or kinematic body, an inertia of 0 for a body kept from turning.
    pub fn mass_data(&self, id: BodyId) -> Result<MassData, WorldError> {
        Ok(MassData {
            mass: self.mass(id)?,
            center: self.local_center(id)?,
            inertia: self.inertia(id)?,
        })
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec2;

    use super::*;
    use crate::def::{BodyDef, ShapeDef};
    use crate::world::StepSettings;

    const DT: f32 = 1.0 / 60.0;

    fn unit_box() -> ShapeDef {
        ShapeDef::Box {
            half_extents: [0.5, 0.5],
            radius: 0.0,
        }
    }

    /// A static ground along y = 0 and a unit box resting on it.
    fn box_on_ground() -> (World, BodyId) {
        let mut w = World::new(StepSettings::default());
        w.create_body(
            &BodyDef::new(ShapeDef::Box {
                half_extents: [20.0, 0.5],
                radius: 0.0,
            })
            .kind(BodyKind::Static)
            .at(0.0, -0.5),
        )
        .unwrap();
        let b = w
            .create_body(&BodyDef::new(unit_box()).at(0.0, 0.5))
            .unwrap();
        (w, b)
    }

    #[test]
    fn damping_and_gravity_scale_act_from_the_next_step_and_bad_values_change_nothing() {
        let mut w = World::new(StepSettings::default());
        let b = w.create_body(&BodyDef::new(unit_box())).unwrap();
        w.set_gravity_scale(b, 0.0).unwrap();
        w.set_linear_damping(b, 2.0).unwrap();
        w.set_angular_damping(b, 1.0).unwrap();
        w.set_velocity(b, Vec2::new(3.0, 0.0), 2.0).unwrap();
        for bad in [-1.0, f32::NAN, f32::INFINITY] {
            assert!(matches!(
                w.set_linear_damping(b, bad),
                Err(WorldError::Invalid { .. })
            ));
            assert!(w.set_angular_damping(b, bad).is_err());
        }
        assert!(w.set_gravity_scale(b, f32::NAN).is_err());
        assert_eq!(
            (
                w.linear_damping(b),
                w.angular_damping(b),
                w.gravity_scale(b)
            ),
            (Ok(2.0), Ok(1.0), Ok(0.0))
        );
        w.step(DT, 4);
        // Four substeps of h = dt/4, each dividing by 1 + h·c (the Padé damping of
        // `integrate_velocity`); no gravity at a scale of 0. 1e-6 relative: f32.
        let h = DT / 4.0;
        let v = w.body(b).unwrap();
        assert!((v.linear_velocity.x / (3.0 / (1.0 + h * 2.0f32).powi(4)) - 1.0).abs() < 1e-6);
        assert!((v.angular_velocity / (2.0 / (1.0 + h).powi(4)) - 1.0).abs() < 1e-6);
        assert_eq!(v.linear_velocity.y, 0.0);
    }

    #[test]
    fn fixed_rotation_stops_the_spin_and_gives_the_inertia_back_when_lifted() {
        let mut w = World::new(StepSettings::default());
        let b = w.create_body(&BodyDef::new(unit_box())).unwrap();
        let inertia = w.inertia(b).unwrap();
        w.set_velocity(b, Vec2::ZERO, 3.0).unwrap();
        w.set_fixed_rotation(b, true).unwrap();
        assert_eq!(w.fixed_rotation(b), Ok(true));
        assert_eq!(w.inertia(b), Ok(0.0));
        assert_eq!(w.body(b).unwrap().angular_velocity, 0.0);
        w.apply_angular_impulse(b, 1.0, true).unwrap();
        w.step(DT, 4);
        assert_eq!(w.body(b).unwrap().angular_velocity, 0.0);
        w.set_fixed_rotation(b, false).unwrap();
        assert_eq!(w.inertia(b), Ok(inertia));
    }

    #[test]
    fn set_awake_sleeps_a_resting_island_at_once_and_disabled_sleep_keeps_it_awake() {
        let (mut w, b) = box_on_ground();
        w.step(DT, 4);
        w.set_awake(b, false).unwrap();
        assert_eq!(w.is_awake(b), Ok(false));
        assert_eq!(w.body(b).unwrap().linear_velocity, Vec2::ZERO);
        w.validate().unwrap();
        // Resting, it stays asleep; woken, it is awake.
        w.step(DT, 4);
        assert_eq!(w.is_awake(b), Ok(false));
        w.set_awake(b, true).unwrap();
        assert_eq!(w.is_awake(b), Ok(true));
        // Without sleep it rests 5 s (ten times the default time to sleep) awake.
        w.set_sleep_enabled(b, false).unwrap();
        assert_eq!(w.sleep_enabled(b), Ok(false));
        for _ in 0..300 {
            w.step(DT, 4);
        }
        assert_eq!(w.is_awake(b), Ok(true));
        w.set_sleep_enabled(b, true).unwrap();
        for _ in 0..60 {
            w.step(DT, 4);
        }
        assert_eq!(w.is_awake(b), Ok(false));
    }

    #[test]
    fn given_mass_data_hold_until_the_shapes_change_and_bad_ones_are_refused() {
        let mut w = World::new(StepSettings::default());
        let b = w
            .create_body(&BodyDef::new(unit_box()).at(1.0, 2.0))
            .unwrap();
        let shapes = w.mass_data(b).unwrap();
        assert_eq!(shapes.mass, 1.0);
        let given = MassData {
            mass: 4.0,
            center: Vec2::new(0.25, 0.0),
            inertia: 2.0,
        };
        w.set_mass_data(b, given).unwrap();
        assert_eq!(w.mass_data(b), Ok(given));
        // The frame stays; the centre moved a quarter metre along it.
        let v = w.body(b).unwrap();
        assert_eq!(v.origin, Vec2::new(1.0, 2.0));
        assert_eq!(v.position, Vec2::new(1.25, 2.0));
        // An impulse responds by the given mass (1e-6 relative: f32).
        w.apply_linear_impulse_to_center(b, Vec2::new(8.0, 0.0), true)
            .unwrap();
        assert!((w.body(b).unwrap().linear_velocity.x / 2.0 - 1.0).abs() < 1e-6);
        w.validate().unwrap();
        for (bad, what) in [
            (MassData { mass: 0.0, ..given }, "zero mass"),
            (
                MassData {
                    mass: -1.0,
                    ..given
                },
                "negative mass",
            ),
            (
                MassData {
                    mass: f32::NAN,
                    ..given
                },
                "NaN mass",
            ),
            (
                MassData {
                    inertia: -1.0,
                    ..given
                },
                "negative inertia",
            ),
            (
                MassData {
                    center: Vec2::new(f32::INFINITY, 0.0),
                    ..given
                },
                "infinite centre",
            ),
        ] {
            assert!(w.set_mass_data(b, bad).is_err(), "{what}");
            assert_eq!(w.mass_data(b), Ok(given), "{what}");
        }
        // A density change computes them from the shapes again.
        let shape = w.body_shapes(b).unwrap().next().unwrap().id;
        w.set_density(shape, 2.0).unwrap();
        let md = w.mass_data(b).unwrap();
        assert_eq!((md.mass, md.center), (2.0, Vec2::ZERO));
        // Only a dynamic body has mass.
        w.set_kind(b, BodyKind::Kinematic).unwrap();
        assert!(w.set_mass_data(b, given).is_err());
    }

    /// Counts lines drawn.
    struct Lines(usize);

    impl crate::DebugDraw for Lines {
        fn draw_segment(&mut self, _: Vec2, _: Vec2, _: [f32; 4]) {
            self.0 += 1;
        }
    }

    #[test]
    fn a_disabled_body_touches_nothing_is_seen_by_nothing_and_comes_back_where_it_was() {
        let (mut w, crate_) = box_on_ground();
        // A second box 3 m above the first: it will fall through the disabled one's place.
        let faller = w
            .create_body(&BodyDef::new(unit_box()).at(0.0, 3.5))
            .unwrap();
        for _ in 0..30 {
            w.step(DT, 4);
        }
        assert_eq!(w.body_contacts(crate_).unwrap().len(), 1);
        let before = w.body(crate_).unwrap();
        let lines = |w: &World| {
            let mut l = Lines(0);
            w.draw(&mut l, &crate::DrawOptions::default());
            l.0
        };
        let drawn = lines(&w);

        w.set_enabled(crate_, false).unwrap();
        w.validate().unwrap();
        assert_eq!(w.is_enabled(crate_), Ok(false));
        // Its touch with the ground ended at once, with the event.
        assert!(w.body_contacts(crate_).unwrap().is_empty());
        assert!(
            w.events()
                .iter()
                .any(|e| matches!(e, crate::Event::ContactEnd { .. }))
        );
        // Queries, the pointer and drawing see nothing of it; impulses do not move it.
        let filter = crate::QueryFilter::default();
        let ray = w.cast_ray_closest(Vec2::new(-5.0, 0.5), Vec2::new(10.0, 0.0), &filter);
        assert!(ray.is_none(), "{ray:?}");
        assert_eq!(w.body_at(Vec2::new(0.0, 0.5)), None);
        assert_eq!(lines(&w), drawn - 4);
        w.apply_linear_impulse_to_center(crate_, Vec2::new(5.0, 0.0), true)
            .unwrap();
        w.explode(&crate::ExplosionDef {
            // Reaches the crate's right face (0.7 m away), not the faller (1.4 m above).
            position: Vec2::new(1.2, 0.5),
            radius: 0.8,
            impulse_per_length: 5.0,
            ..crate::ExplosionDef::default()
        })
        .unwrap();
        for _ in 0..120 {
            w.step(DT, 4);
            w.validate().unwrap();
        }
        // Not integrated (no gravity), not solved: the faller fell through its place to the
        // ground, where it rests inside it.
        let held = w.body(crate_).unwrap();
        assert_eq!((held.position, held.angle), (before.position, before.angle));
        let fallen = w.body(faller).unwrap().position;
        assert!((fallen.y - 0.5).abs() < 0.02, "{fallen}");
        assert!(w.body_contacts(crate_).unwrap().is_empty());

        // Back where it was, awake, and at once it pushes the faller out of itself.
        w.set_enabled(crate_, true).unwrap();
        w.validate().unwrap();
        assert!(w.is_enabled(crate_).unwrap() && w.body(crate_).unwrap().awake);
        assert_eq!(lines(&w), drawn);
        assert_eq!(
            w.body_at(Vec2::new(0.3, 0.2)),
            Some(faller),
            "the later shape is on top"
        );
        for _ in 0..120 {
            w.step(DT, 4);
            w.validate().unwrap();
        }
        assert!(!w.body_contacts(crate_).unwrap().is_empty());
        let (a, b) = (w.body(crate_).unwrap(), w.body(faller).unwrap());
        // Pushed apart: no longer overlapping (their centres at least 1 m apart, less the
        // 5 mm slop Box2D's soft contacts keep).
        assert!((a.position - b.position).length() > 0.99, "{a:?} {b:?}");
        assert_eq!(w.non_finite_bodies(), 0);
    }

    #[test]
    fn a_disabled_body_s_joints_are_kept_unsolved_and_join_its_island_again() {
        let mut w = World::new(StepSettings {
            gravity: Vec2::ZERO,
            ..StepSettings::default()
        });
        let a = w.create_body(&BodyDef::new(unit_box())).unwrap();
        let b = w
            .create_body(&BodyDef::new(unit_box()).at(2.0, 0.0))
            .unwrap();
        let hinge = w
            .create_joint(&crate::JointDef::hinge([a, b], [1.0, 0.0]))
            .unwrap();
        w.step(DT, 4);
        assert_eq!(w.island_of(a).unwrap(), w.island_of(b).unwrap());
        w.set_enabled(a, false).unwrap();
        assert_eq!(w.island_of(a), Ok(None));
        assert_eq!(w.body_joints(a).unwrap(), [hinge]);
        // B drifts off: the hinge does not hold it while A is out.
        w.set_velocity(b, Vec2::new(1.0, 0.0), 0.0).unwrap();
        for _ in 0..60 {
            w.step(DT, 4);
            w.validate().unwrap();
        }
        let gap = w.body(b).unwrap().position.x - w.body(a).unwrap().position.x;
        assert!((gap - 3.0).abs() < 1e-3, "{gap}");
        // Back: one island again, and the hinge pulls the anchors together (within 1 cm
        // in 2 s, the soft joint's spring at its default stiffness).
        w.set_velocity(b, Vec2::ZERO, 0.0).unwrap();
        w.set_enabled(a, true).unwrap();
        w.validate().unwrap();
        assert_eq!(w.island_of(a).unwrap(), w.island_of(b).unwrap());
        for _ in 0..120 {
            w.step(DT, 4);
        }
        let [pa, pb] = w.joint_anchors(hinge).unwrap();
        assert!((pa - pb).length() < 0.01, "{pa} {pb}");
        // Disabling twice, or enabling an enabled body, changes nothing; a stale id is refused.
        w.set_enabled(a, true).unwrap();
        w.destroy_body(b).unwrap();
        assert!(w.set_enabled(b, false).is_err());
        w.set_enabled(a, false).unwrap();
        w.set_enabled(a, false).unwrap();
        w.validate().unwrap();
    }

    #[test]
    fn disabling_is_the_same_on_any_thread_count_and_through_a_snapshot() {
        // A pile of 200 boxes; a third of them disabled at step 20, back at step 60.
        let run = |threads: usize, snapshot_at: Option<usize>| {
            let mut w = World::new(StepSettings::default());
            w.set_thread_count(threads);
            w.create_body(
                &BodyDef::new(ShapeDef::Box {
                    half_extents: [30.0, 0.5],
                    radius: 0.0,
                })
                .kind(BodyKind::Static)
                .at(0.0, -0.5),
            )
            .unwrap();
            let boxes: Vec<BodyId> = (0..200)
                .map(|k| {
                    let (x, y) = ((k % 20) as f32 * 1.1 - 10.0, 0.5 + (k / 20) as f32 * 1.05);
                    w.create_body(&BodyDef::new(unit_box()).at(x, y)).unwrap()
                })
                .collect();
            for step in 0..100 {
                if step == 20 || step == 60 {
                    for &b in boxes.iter().step_by(3) {
                        w.set_enabled(b, step == 60).unwrap();
                    }
                }
                if snapshot_at == Some(step) {
                    w = World::from_snapshot(w.snapshot()).unwrap();
                    w.set_thread_count(threads);
                }
                w.step(DT, 4);
            }
            w.validate().unwrap();
            assert_eq!(w.non_finite_bodies(), 0);
            w.state_hash()
        };
        let one = run(1, None);
        assert_eq!(run(4, None), one);
        assert_eq!(run(2, Some(40)), one);
    }
}
