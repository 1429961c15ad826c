//! A joint's state as a game reads it (angle, translation, length), its thresholds and its
//! tag: Box2D v3's `b2RevoluteJoint_GetAngle`, `b2PrismaticJoint_GetTranslation`,
//! `b2DistanceJoint_GetCurrentLength`, `b2Joint_SetForceThreshold` and `b2Joint_SetUserData`.

use glam::Vec2;

use super::{World, WorldError};
use crate::id::JointId;
use crate::joint::JointKind;
use crate::math::{Transform, dot};

/// A joint's state now, its thresholds and its tag. A call that does not fit the joint's
/// kind (the angle of a slider) is [`WorldError::Invalid`]; a stale id is
/// [`WorldError::NoJoint`].
///
/// ```
/// use tumble_physics::{BodyDef, BodyKind, Event, JointDef, ShapeDef, StepSettings, World};
///
/// let mut world = World::new(StepSettings::default());
/// let pin = world.create_body(&BodyDef::new(ShapeDef::Circle { radius: 0.1 }).kind(BodyKind::Static).at(0.0, 5.0)).unwrap();
/// let bob = world.create_body(&BodyDef::new(ShapeDef::Circle { radius: 0.3 }).at(2.0, 5.0)).unwrap();
/// // A hinge that reports when it pulls with more than 5 N.
/// let hinge = world.create_joint(&JointDef::hinge([pin, bob], [0.0, 5.0]).with_thresholds(5.0, f32::INFINITY)).unwrap();
/// let mut reported = false;
/// for _ in 0..60 {
///     world.step(1.0 / 60.0, 4);
///     reported |= world.events().iter().any(|e| matches!(e, Event::JointThreshold { joint, .. } if *joint == hinge));
/// }
/// // The bob swung down: the angle of B relative to A went negative (clockwise).
/// assert!(world.revolute_angle(hinge).unwrap() < -0.5);
/// assert!(reported);
/// ```
impl World {
    /// A joint's frames in the world now: A's and B's.
    fn joint_frames(&self, k: usize) -> [Transform; 2] {
        let j = &self.joints.list[k];
        [
            self.body_frame(j.body_a as usize).compose(j.local_a),
            self.body_frame(j.body_b as usize).compose(j.local_b),
        ]
    }

    /// A revolute joint's angle now: B's turn relative to A since the joint was made
    /// (rad, in (-π, π]), as its limits count it.
    pub fn revolute_angle(&self, id: JointId) -> Result<f32, WorldError> {
        let k = self.joint_of_kind(id, "revolute", |k| matches!(k, JointKind::Revolute(_)))?;
        let [a, b] = self.joint_frames(k);
        Ok(a.q.inv_mul(b.q).angle())
    }

    /// A prismatic (or wheel) joint's translation now: how far B's anchor lies from A's
    /// along the axis fixed in A (m), as its limits count it.
    pub fn prismatic_translation(&self, id: JointId) -> Result<f32, WorldError> {
        let k = self.joint_of_kind(id, "prismatic or wheel", |k| {
            matches!(k, JointKind::Prismatic(_) | JointKind::Wheel(_))
        })?;
        let [a, b] = self.joint_frames(k);
        Ok(dot(a.q.apply(Vec2::X), b.p - a.p))
    }

    /// A distance joint's length now: the distance between its anchors (m).
    pub fn distance_length(&self, id: JointId) -> Result<f32, WorldError> {
        let k = self.joint_of_kind(id, "distance", |k| matches!(k, JointKind::Distance(_)))?;
        let [a, b] = self.joint_frames(k);
        Ok((b.p - a.p).length())
    }

    /// Sets the reaction force (N) and torque (N·m) past which a step reports
    /// [`crate::Event::JointThreshold`] for the joint (`f32::INFINITY`: never). Each must be
    /// ≥ 0 and not NaN.
    pub fn set_joint_thresholds(
        &mut self,
        id: JointId,
        force: f32,
        torque: f32,
    ) -> Result<(), WorldError> {
        let k = self.joint_slot(id)?;
        for (what, v) in [("force threshold", force), ("torque threshold", torque)] {
            if v.is_nan() || v < 0.0 {
                return Err(WorldError::Invalid {
                    what: format!("{what} {v} for {id}"),
                    why: "it must be >= 0 (f32::INFINITY for none)".into(),
                });
            }
        }
        self.edit_joints();
        let j = &mut self.joints.list[k];
        j.force_threshold = force;
        j.torque_threshold = torque;
        Ok(())
    }

    /// A joint's force (N) and torque (N·m) thresholds.
    pub fn joint_thresholds(&self, id: JointId) -> Result<(f32, f32), WorldError> {
        let j = &self.joints.list[self.joint_slot(id)?];
        Ok((j.force_threshold, j.torque_threshold))
    }

    /// Tags a joint with a number of the caller's choosing (Box2D's `b2Joint_SetUserData`);
    /// a new joint carries 0, snapshots keep it, the step never reads it.
    pub fn set_joint_user_data(&mut self, id: JointId, user_data: u64) -> Result<(), WorldError> {
        let k = self.joint_slot(id)?;
        self.edit_joints();
        self.joints.list[k].user_data = user_data;
        Ok(())
    }

    /// The tag [`World::set_joint_user_data`] gave a joint (0 if none).
    pub fn joint_user_data(&self, id: JointId) -> Result<u64, WorldError> {
        Ok(self.joints.list[self.joint_slot(id)?].user_data)
    }

    /// Joint `id`'s slot if it is of the kind `is` accepts.
    fn joint_of_kind(
        &self,
        id: JointId,
        kind: &str,
        is: impl Fn(&JointKind) -> bool,
    ) -> Result<usize, WorldError> {
        let k = self.joint_slot(id)?;
        if is(&self.joints.list[k].kind) {
            Ok(k)
        } else {
            Err(WorldError::Invalid {
                what: format!("{id}"),
                why: format!("it is not a {kind} joint"),
            })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::def::{BodyDef, BodyKind, ShapeDef};
    use crate::id::BodyId;
    use crate::joint::JointDef;
    use crate::world::{Event, StepSettings};

    const DT: f32 = 1.0 / 60.0;

    /// A static pin at (0, 5) and a 1 kg box hanging from it by a hinge 2 m above its
    /// centre, or 2 m to the side to swing.
    fn pendulum(hanging: bool) -> (World, BodyId, JointId) {
        let mut w = World::new(StepSettings::default());
        let pin = w
            .create_body(
                &BodyDef::new(ShapeDef::Circle { radius: 0.1 })
                    .kind(BodyKind::Static)
                    .at(0.0, 5.0),
            )
            .unwrap();
        let at = if hanging { (0.0, 3.0) } else { (2.0, 5.0) };
        let bob = w
            .create_body(
                &BodyDef::new(ShapeDef::Box {
                    half_extents: [0.5, 0.5],
                    radius: 0.0,
                })
                .at(at.0, at.1),
            )
            .unwrap();
        let j = w
            .create_joint(&JointDef::hinge([pin, bob], [0.0, 5.0]))
            .unwrap();
        (w, bob, j)
    }

    #[test]
    fn a_hinge_reports_each_step_its_pull_passes_the_threshold_and_the_game_can_break_it() {
        // Hanging at rest, the hinge holds the box's weight: m g = 10 N (the default gravity).
        let (mut w, bob, j) = pendulum(true);
        // (Kept awake: a sleeping joint reports nothing.)
        w.set_sleep_enabled(bob, false).unwrap();
        for _ in 0..20 {
            w.step(DT, 4);
        }
        let (f, _) = w.joint_reaction(j).unwrap();
        assert!((f.length() - 10.0).abs() < 0.01, "{f}");
        // Under the weight: reported every step, with its size; over it: never.
        w.set_joint_thresholds(j, 9.5, f32::INFINITY).unwrap();
        w.step(DT, 4);
        match w.events() {
            [Event::JointThreshold { joint, force, .. }] => {
                assert_eq!(*joint, j);
                assert!((force - 10.0).abs() < 0.01, "{force}");
            }
            other => panic!("{other:?}"),
        }
        w.set_joint_thresholds(j, 10.5, f32::INFINITY).unwrap();
        for _ in 0..10 {
            w.step(DT, 4);
            assert!(w.events().is_empty(), "{:?}", w.events());
        }
        // The game breaks it when told: the box falls.
        w.set_joint_thresholds(j, 9.5, 1.0).unwrap();
        assert_eq!(w.joint_thresholds(j), Ok((9.5, 1.0)));
        w.step(DT, 4);
        for e in w.events().to_vec() {
            if let Event::JointThreshold { joint, .. } = e {
                w.destroy_joint(joint).unwrap();
            }
        }
        for _ in 0..30 {
            w.step(DT, 4);
        }
        // Free, it falls 1.25 m in 0.5 s from y = 3.
        assert!(w.body(bob).unwrap().position.y < 2.0);
        // Refused: NaN and negative thresholds; the joint is gone.
        let (mut w, _, j) = pendulum(true);
        assert!(w.set_joint_thresholds(j, f32::NAN, 1.0).is_err());
        assert!(w.set_joint_thresholds(j, 1.0, -1.0).is_err());
        assert_eq!(w.joint_thresholds(j), Ok((f32::INFINITY, f32::INFINITY)));
    }

    #[test]
    fn a_sleeping_joint_reports_nothing() {
        let (mut w, bob, j) = pendulum(true);
        w.set_joint_thresholds(j, 0.0, 0.0).unwrap();
        let mut reported = 0;
        for _ in 0..300 {
            w.step(DT, 4);
            reported += w.events().len();
        }
        // It reported while awake, then the pendulum slept (after 0.5 s at rest).
        assert!(reported > 10);
        assert_eq!(w.is_awake(bob), Ok(false));
        w.step(DT, 4);
        assert!(w.events().is_empty());
    }

    #[test]
    fn angle_translation_and_length_read_the_poses_as_the_limits_count_them() {
        let (mut w, bob, j) = pendulum(false);
        for _ in 0..20 {
            w.step(DT, 4);
        }
        // The pin does not turn: the hinge's angle is the box's (f32 atan2 of the same
        // rotation, composed with an identity frame: 1e-6).
        let angle = w.revolute_angle(j).unwrap();
        assert!(angle < -0.1);
        assert!((angle - w.body(bob).unwrap().angle).abs() < 1e-6);
        assert!(w.prismatic_translation(j).is_err());
        assert!(w.distance_length(j).is_err());

        let mut w = World::new(StepSettings {
            gravity: Vec2::ZERO,
            ..StepSettings::default()
        });
        let circle = ShapeDef::Circle { radius: 0.2 };
        let a = w
            .create_body(&BodyDef::new(circle.clone()).kind(BodyKind::Static))
            .unwrap();
        let b = w.create_body(&BodyDef::new(circle).at(1.0, 0.0)).unwrap();
        let slider = w
            .create_joint(&JointDef::Prismatic {
                bodies: [a, b],
                anchor: [1.0, 0.0],
                axis: [1.0, 0.0],
                limit: None,
                motor: None,
                spring: None,
                collide_connected: false,
                force_threshold: f32::INFINITY,
                torque_threshold: f32::INFINITY,
            })
            .unwrap();
        let rod = w
            .create_joint(&JointDef::Distance {
                bodies: [a, b],
                anchors: [[0.0, 0.0], [1.0, 0.0]],
                length: None,
                limit: None,
                spring: Some(crate::joint::Spring {
                    hertz: 0.0,
                    damping_ratio: 0.0,
                }),
                collide_connected: false,
                force_threshold: f32::INFINITY,
                torque_threshold: f32::INFINITY,
            })
            .unwrap();
        w.set_transform(b, Vec2::new(1.7, 0.0), 0.0).unwrap();
        assert!((w.prismatic_translation(slider).unwrap() - 0.7).abs() < 1e-6);
        assert!((w.distance_length(rod).unwrap() - 1.7).abs() < 1e-6);
        assert!(w.revolute_angle(slider).is_err());
    }

    #[test]
    fn joints_keep_their_tags_and_thresholds_through_a_snapshot() {
        let (mut w, _, j) = pendulum(true);
        w.set_joint_user_data(j, 99).unwrap();
        w.set_joint_thresholds(j, 9.5, f32::INFINITY).unwrap();
        w.step(DT, 4);
        let mut copy = World::from_snapshot(w.snapshot()).unwrap();
        assert_eq!(copy.joint_user_data(j), Ok(99));
        assert_eq!(copy.joint_thresholds(j), Ok((9.5, f32::INFINITY)));
        w.step(DT, 4);
        copy.step(DT, 4);
        assert_eq!(w.events(), copy.events());
        assert_eq!(w.events().len(), 1);
        // And through JSON, which has no infinity.
        let json = serde_json::to_string(&w.snapshot()).unwrap();
        let back: crate::WorldSnapshot = serde_json::from_str(&json).unwrap();
        let back = World::from_snapshot(back).unwrap();
        assert_eq!(back.joint_thresholds(j), Ok((9.5, f32::INFINITY)));
    }
}
