//! Forces and torques: applied between steps, they act through the next step (each substep
//! integrates them as it integrates gravity) and are then cleared, as in Box2D v3
//! (`b2Body_ApplyForce`, cleared in `b2FinalizeBodiesTask`). A world where no body has a
//! force integrates exactly as before: the solver is told there are none.

use glam::Vec2;

use super::bodies::finite;
use super::{World, WorldError};
use crate::id::BodyId;
use crate::math::cross;

/// Forces and torques, each acting through the next step only: a game that pushes every
/// step applies its force every step. Only an awake dynamic body responds; with `wake` false
/// a sleeping body is left as it is (Box2D's rule), and a non-finite value is refused.
///
/// ```
/// use tumble_physics::{BodyDef, ShapeDef, StepSettings, Vec2, World};
///
/// let mut world = World::new(StepSettings { gravity: Vec2::ZERO, ..StepSettings::default() });
/// let ball = world.create_body(&BodyDef::new(ShapeDef::Circle { radius: 0.5 })).unwrap();
/// let mass = world.mass(ball).unwrap();
/// // 1 s of thrust at 2 m/s², one step at a time.
/// for _ in 0..60 {
///     world.apply_force_to_center(ball, Vec2::new(2.0 * mass, 0.0), true).unwrap();
///     world.step(1.0 / 60.0, 4);
/// }
/// assert!((world.body(ball).unwrap().linear_velocity.x - 2.0).abs() < 1e-4);
/// // Not applied again, it acts no more.
/// world.step(1.0 / 60.0, 4);
/// assert!((world.body(ball).unwrap().linear_velocity.x - 2.0).abs() < 1e-4);
/// ```
impl World {
    /// Applies a force (N) at a world point through the next step: off the centre of mass
    /// it turns the body too (Box2D's `b2Body_ApplyForce`).
    pub fn apply_force(
        &mut self,
        id: BodyId,
        force: Vec2,
        point: Vec2,
        wake: bool,
    ) -> Result<(), WorldError> {
        let i = self.slot(id)?;
        finite("force", force)?;
        finite("point", point)?;
        if self.impulse_target(i, wake) {
            let r = point - self.bodies.sims[i].xf.p;
            self.bodies.add_force(i as u32, force, cross(r, force));
        }
        Ok(())
    }

    /// Applies a force (N) at the body's centre of mass through the next step.
    pub fn apply_force_to_center(
        &mut self,
        id: BodyId,
        force: Vec2,
        wake: bool,
    ) -> Result<(), WorldError> {
        let i = self.slot(id)?;
        finite("force", force)?;
        if self.impulse_target(i, wake) {
            self.bodies.add_force(i as u32, force, 0.0);
        }
        Ok(())
    }

    /// Applies a torque (N·m) through the next step.
    pub fn apply_torque(&mut self, id: BodyId, torque: f32, wake: bool) -> Result<(), WorldError> {
        let i = self.slot(id)?;
        if !torque.is_finite() {
            return Err(WorldError::Invalid {
                what: format!("torque {torque} on {id}"),
                why: "it must be finite".into(),
            });
        }
        if self.impulse_target(i, wake) {
            self.bodies.add_force(i as u32, Vec2::ZERO, torque);
        }
        Ok(())
    }

    /// The force and torque applied to a body since the last step (what the next step
    /// will integrate).
    pub fn applied_force(&self, id: BodyId) -> Result<(Vec2, f32), WorldError> {
        let f = self.bodies.forces[self.slot(id)?];
        Ok((f.force, f.torque))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::def::{BodyDef, BodyKind, ShapeDef};
    use crate::world::StepSettings;

    const DT: f32 = 1.0 / 60.0;

    /// A 2 x 1 box (density 1: m = 2, I = m (w² + h²) / 12 = 5/6) floating without gravity.
    fn floating_box() -> (World, BodyId) {
        let mut w = World::new(StepSettings {
            gravity: Vec2::ZERO,
            ..StepSettings::default()
        });
        let b = w
            .create_body(&BodyDef::new(ShapeDef::Box {
                half_extents: [1.0, 0.5],
                radius: 0.0,
            }))
            .unwrap();
        (w, b)
    }

    #[test]
    fn a_force_off_the_centre_pushes_and_turns_for_one_step_then_is_cleared() {
        let (mut w, b) = floating_box();
        let (m, i) = (w.mass(b).unwrap(), w.inertia(b).unwrap());
        // 3 N upwards at the box's right end, 1 m from its centre: a torque of 3 N·m.
        let f = Vec2::new(0.0, 3.0);
        w.apply_force(b, f, Vec2::new(1.0, 0.0), true).unwrap();
        w.apply_torque(b, -0.5, true).unwrap();
        assert_eq!(w.applied_force(b), Ok((f, 2.5)));
        w.step(DT, 4);
        assert_eq!(w.applied_force(b), Ok((Vec2::ZERO, 0.0)));
        // Four substeps of h each add h·F/m and h·τ/I: dt·F/m and dt·τ/I in all (1e-6
        // relative: four f32 additions).
        let v = w.body(b).unwrap();
        let (dv, dw) = (DT * 3.0 / m, DT * 2.5 / i);
        assert!((v.linear_velocity.y / dv - 1.0).abs() < 1e-6, "{v:?}");
        assert!((v.angular_velocity / dw - 1.0).abs() < 1e-6, "{v:?}");
        // Cleared: the next step coasts.
        w.step(DT, 4);
        let after = w.body(b).unwrap();
        assert_eq!(after.linear_velocity, v.linear_velocity);
        assert_eq!(after.angular_velocity, v.angular_velocity);
    }

    #[test]
    fn forces_add_up_wake_only_when_asked_and_refuse_non_finite_input() {
        let (mut w, b) = floating_box();
        w.apply_force_to_center(b, Vec2::X, true).unwrap();
        w.apply_force_to_center(b, Vec2::Y, true).unwrap();
        assert_eq!(w.applied_force(b), Ok((Vec2::ONE, 0.0)));
        // Refused whole, the pending force unchanged.
        let nan = Vec2::new(f32::NAN, 0.0);
        assert!(matches!(
            w.apply_force_to_center(b, nan, true),
            Err(WorldError::Invalid { .. })
        ));
        assert!(w.apply_force(b, Vec2::X, nan, true).is_err());
        assert!(w.apply_torque(b, f32::INFINITY, true).is_err());
        assert_eq!(w.applied_force(b), Ok((Vec2::ONE, 0.0)));
        w.step(DT, 4);
        // Asleep (no motion, for long enough), it ignores a force without `wake`...
        w.set_velocity(b, Vec2::ZERO, 0.0).unwrap();
        for _ in 0..120 {
            w.step(DT, 4);
        }
        assert_eq!(w.is_awake(b), Ok(false));
        w.apply_force_to_center(b, Vec2::X, false).unwrap();
        w.apply_torque(b, 1.0, false).unwrap();
        assert_eq!(w.applied_force(b), Ok((Vec2::ZERO, 0.0)));
        // ...and takes one with it, awake.
        w.apply_torque(b, 1.0, true).unwrap();
        assert_eq!(w.is_awake(b), Ok(true));
        w.step(DT, 4);
        assert!(w.body(b).unwrap().angular_velocity > 0.0);
        // A static body takes none; a stale id is refused.
        let wall = w
            .create_body(&BodyDef::new(ShapeDef::Circle { radius: 1.0 }).kind(BodyKind::Static))
            .unwrap();
        w.apply_force_to_center(wall, Vec2::X, true).unwrap();
        assert_eq!(w.applied_force(wall), Ok((Vec2::ZERO, 0.0)));
        w.destroy_body(b).unwrap();
        assert_eq!(w.apply_torque(b, 1.0, true), Err(WorldError::NoBody(b)));
    }

    #[test]
    fn a_snapshot_keeps_the_forces_applied_before_it() {
        let (mut w, b) = floating_box();
        w.apply_force(b, Vec2::new(1.0, 2.0), Vec2::new(0.5, 0.5), true)
            .unwrap();
        let mut copy = World::from_snapshot(w.snapshot()).unwrap();
        w.step(DT, 4);
        copy.step(DT, 4);
        assert_eq!(w.state_hash(), copy.state_hash());
        assert_ne!(w.body(b).unwrap().angular_velocity, 0.0);
    }
}
