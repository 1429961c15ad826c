//! Joints as scene files give them (CONTRACT.md section 5): bodies by index, anchors and axes
//! in world coordinates at the poses the scene starts with. `JointDef::build` turns one into
//! a [`Joint`] in its bodies' frames; `JointDef::validate` refuses what cannot be built.

use glam::Vec2;
use serde::{Deserialize, Serialize};

use super::{Distance, Joint, JointKind, JointStep, Motor, Prismatic, Revolute, Weld, Wheel};
use crate::error::SceneError;
use crate::id::BodyId;
use crate::math::{Rot, Transform};
use crate::softness::Softness;

/// A spring on a joint's free direction.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct Spring {
    /// Stiffness (Hz, >= 0; 0 is slack).
    pub hertz: f32,
    /// Damping ratio (>= 0).
    #[serde(default)]
    pub damping_ratio: f32,
}

/// A motor on an angle.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct AngularMotor {
    /// Target rate (rad/s).
    pub speed: f32,
    /// Most torque (N·m, >= 0).
    pub max_torque: f32,
}

/// A motor along an axis.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct LinearMotor {
    /// Target speed (m/s).
    pub speed: f32,
    /// Most force (N, >= 0).
    pub max_force: f32,
}

/// An optional field written without RON's `Some(..)` (`limit: (-1, 1)`), as the scene's
/// other optional fields are.
fn present<'de, D: serde::Deserializer<'de>, T: Deserialize<'de>>(
    d: D,
) -> Result<Option<T>, D::Error> {
    T::deserialize(d).map(Some)
}

impl Spring {
    /// The soft-step coefficients of an optional spring for substep `h` (none: zero, a
    /// spring that does nothing).
    pub(crate) fn softness(spring: Option<Spring>, h: f32) -> Softness {
        spring.map_or(Default::default(), |sp| {
            Softness::new(sp.hertz, sp.damping_ratio, h)
        })
    }
}

fn is_false(b: &bool) -> bool {
    !*b
}
fn infinite() -> f32 {
    f32::INFINITY
}
fn is_infinite(x: &f32) -> bool {
    *x == f32::INFINITY
}
fn one() -> f32 {
    1.0
}
fn correction() -> f32 {
    0.3
}

/// A joint in a scene file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub enum JointDef {
    /// A hinge at `anchor`.
    Revolute {
        /// Body A and body B (in a scene file, by their index in `bodies`).
        #[serde(with = "crate::id::scene_bodies")]
        #[cfg_attr(feature = "schema", schemars(with = "[usize; 2]"))]
        bodies: [BodyId; 2],
        /// The hinge point (m, world, at the start).
        anchor: [f32; 2],
        /// Bounds of B's angle relative to A from the start, −0.99π ≤ lower ≤ upper ≤ 0.99π.
        #[serde(
            default,
            deserialize_with = "present",
            skip_serializing_if = "Option::is_none"
        )]
        limit: Option<[f32; 2]>,
        /// Drives the angle's rate.
        #[serde(
            default,
            deserialize_with = "present",
            skip_serializing_if = "Option::is_none"
        )]
        motor: Option<AngularMotor>,
        /// Pulls the angle back to its start.
        #[serde(
            default,
            deserialize_with = "present",
            skip_serializing_if = "Option::is_none"
        )]
        spring: Option<Spring>,
        /// Whether the two bodies touch.
        #[serde(default, skip_serializing_if = "is_false")]
        collide_connected: bool,
        /// Reaction force (N, >= 0) past which a step reports a `joint_threshold` event
        /// (default: none; the joint is not destroyed: the game decides).
        #[serde(default = "infinite", skip_serializing_if = "is_infinite")]
        force_threshold: f32,
        /// Reaction torque (N·m, >= 0) past which a step reports one (default: none).
        #[serde(default = "infinite", skip_serializing_if = "is_infinite")]
        torque_threshold: f32,
        /// B's hinge point at the start where it is not `anchor` (m, world): a joint that
        /// starts stretched and pulls the two points together (Solver2D's stretched chain).
        #[serde(
            default,
            deserialize_with = "present",
            skip_serializing_if = "Option::is_none"
        )]
        anchor_b: Option<[f32; 2]>,
    },
    /// B slides along `axis` (fixed in A) without turning relative to A.
    Prismatic {
        /// Body A and body B (in a scene file, by their index in `bodies`).
        #[serde(with = "crate::id::scene_bodies")]
        #[cfg_attr(feature = "schema", schemars(with = "[usize; 2]"))]
        bodies: [BodyId; 2],
        /// A point on the axis (m, world).
        anchor: [f32; 2],
        /// The direction of sliding (world, non-zero).
        axis: [f32; 2],
        /// Bounds of the translation (m).
        #[serde(
            default,
            deserialize_with = "present",
            skip_serializing_if = "Option::is_none"
        )]
        limit: Option<[f32; 2]>,
        /// Drives the speed along the axis.
        #[serde(
            default,
            deserialize_with = "present",
            skip_serializing_if = "Option::is_none"
        )]
        motor: Option<LinearMotor>,
        /// Pulls the translation back to 0.
        #[serde(
            default,
            deserialize_with = "present",
            skip_serializing_if = "Option::is_none"
        )]
        spring: Option<Spring>,
        /// Whether the two bodies touch.
        #[serde(default, skip_serializing_if = "is_false")]
        collide_connected: bool,
        /// Reaction force (N, >= 0) past which a step reports a `joint_threshold` event
        /// (default: none; the joint is not destroyed: the game decides).
        #[serde(default = "infinite", skip_serializing_if = "is_infinite")]
        force_threshold: f32,
        /// Reaction torque (N·m, >= 0) past which a step reports one (default: none).
        #[serde(default = "infinite", skip_serializing_if = "is_infinite")]
        torque_threshold: f32,
    },
    /// B slides along `axis` on a spring and turns freely (a wheel on its suspension).
    Wheel {
        /// Body A (the chassis) and body B (the wheel) (in a scene file, by their index in `bodies`).
        #[serde(with = "crate::id::scene_bodies")]
        #[cfg_attr(feature = "schema", schemars(with = "[usize; 2]"))]
        bodies: [BodyId; 2],
        /// The wheel's centre (m, world).
        anchor: [f32; 2],
        /// The suspension's direction (world, non-zero).
        axis: [f32; 2],
        /// Bounds of the translation (m).
        #[serde(
            default,
            deserialize_with = "present",
            skip_serializing_if = "Option::is_none"
        )]
        limit: Option<[f32; 2]>,
        /// Drives the wheel's rotation.
        #[serde(
            default,
            deserialize_with = "present",
            skip_serializing_if = "Option::is_none"
        )]
        motor: Option<AngularMotor>,
        /// The suspension (default 1 Hz, damping ratio 0.7).
        #[serde(
            default,
            deserialize_with = "present",
            skip_serializing_if = "Option::is_none"
        )]
        spring: Option<Spring>,
        /// Whether the two bodies touch.
        #[serde(default, skip_serializing_if = "is_false")]
        collide_connected: bool,
        /// Reaction force (N, >= 0) past which a step reports a `joint_threshold` event
        /// (default: none; the joint is not destroyed: the game decides).
        #[serde(default = "infinite", skip_serializing_if = "is_infinite")]
        force_threshold: f32,
        /// Reaction torque (N·m, >= 0) past which a step reports one (default: none).
        #[serde(default = "infinite", skip_serializing_if = "is_infinite")]
        torque_threshold: f32,
    },
    /// Keeps two anchors `length` apart.
    Distance {
        /// Body A and body B (in a scene file, by their index in `bodies`).
        #[serde(with = "crate::id::scene_bodies")]
        #[cfg_attr(feature = "schema", schemars(with = "[usize; 2]"))]
        bodies: [BodyId; 2],
        /// The anchor on A and the anchor on B (m, world).
        anchors: [[f32; 2]; 2],
        /// Rest length (m; default: the anchors' distance at the start).
        #[serde(
            default,
            deserialize_with = "present",
            skip_serializing_if = "Option::is_none"
        )]
        length: Option<f32>,
        /// Bounds of the length (m), with a spring.
        #[serde(
            default,
            deserialize_with = "present",
            skip_serializing_if = "Option::is_none"
        )]
        limit: Option<[f32; 2]>,
        /// Makes the length soft; `{"hertz": 0}` with a limit `[0, l]` is a rope.
        #[serde(
            default,
            deserialize_with = "present",
            skip_serializing_if = "Option::is_none"
        )]
        spring: Option<Spring>,
        /// Whether the two bodies touch.
        #[serde(default, skip_serializing_if = "is_false")]
        collide_connected: bool,
        /// Reaction force (N, >= 0) past which a step reports a `joint_threshold` event
        /// (default: none; the joint is not destroyed: the game decides).
        #[serde(default = "infinite", skip_serializing_if = "is_infinite")]
        force_threshold: f32,
        /// Reaction torque (N·m, >= 0) past which a step reports one (default: none).
        #[serde(default = "infinite", skip_serializing_if = "is_infinite")]
        torque_threshold: f32,
    },
    /// Glues B to A at `anchor`.
    Weld {
        /// Body A and body B (in a scene file, by their index in `bodies`).
        #[serde(with = "crate::id::scene_bodies")]
        #[cfg_attr(feature = "schema", schemars(with = "[usize; 2]"))]
        bodies: [BodyId; 2],
        /// The weld point (m, world).
        anchor: [f32; 2],
        /// Linear stiffness (Hz, >= 0; 0 is rigid).
        #[serde(default)]
        linear_hertz: f32,
        /// Angular stiffness (Hz, >= 0; 0 is rigid).
        #[serde(default)]
        angular_hertz: f32,
        /// Linear damping ratio (>= 0).
        #[serde(default = "one")]
        linear_damping_ratio: f32,
        /// Angular damping ratio (>= 0).
        #[serde(default = "one")]
        angular_damping_ratio: f32,
        /// Whether the two bodies touch.
        #[serde(default, skip_serializing_if = "is_false")]
        collide_connected: bool,
        /// Reaction force (N, >= 0) past which a step reports a `joint_threshold` event
        /// (default: none; the joint is not destroyed: the game decides).
        #[serde(default = "infinite", skip_serializing_if = "is_infinite")]
        force_threshold: f32,
        /// Reaction torque (N·m, >= 0) past which a step reports one (default: none).
        #[serde(default = "infinite", skip_serializing_if = "is_infinite")]
        torque_threshold: f32,
    },
    /// Drives B towards an offset pose in A's frame.
    Motor {
        /// Body A and body B (in a scene file, by their index in `bodies`).
        #[serde(with = "crate::id::scene_bodies")]
        #[cfg_attr(feature = "schema", schemars(with = "[usize; 2]"))]
        bodies: [BodyId; 2],
        /// B's origin in A's frame (m; default: where B starts).
        #[serde(
            default,
            deserialize_with = "present",
            skip_serializing_if = "Option::is_none"
        )]
        linear_offset: Option<[f32; 2]>,
        /// B's angle less A's (rad; default: as they start).
        #[serde(
            default,
            deserialize_with = "present",
            skip_serializing_if = "Option::is_none"
        )]
        angular_offset: Option<f32>,
        /// Most force (N, >= 0; default 1).
        #[serde(default = "one")]
        max_force: f32,
        /// Most torque (N·m, >= 0; default 1).
        #[serde(default = "one")]
        max_torque: f32,
        /// Share of the error corrected per substep's worth of time (0 to 1; default 0.3).
        #[serde(default = "correction")]
        correction_factor: f32,
        /// Whether the two bodies touch.
        #[serde(default, skip_serializing_if = "is_false")]
        collide_connected: bool,
        /// Reaction force (N, >= 0) past which a step reports a `joint_threshold` event
        /// (default: none; the joint is not destroyed: the game decides).
        #[serde(default = "infinite", skip_serializing_if = "is_infinite")]
        force_threshold: f32,
        /// Reaction torque (N·m, >= 0) past which a step reports one (default: none).
        #[serde(default = "infinite", skip_serializing_if = "is_infinite")]
        torque_threshold: f32,
    },
    /// A and B never touch; nothing else.
    Filter {
        /// Body A and body B (in a scene file, by their index in `bodies`).
        #[serde(with = "crate::id::scene_bodies")]
        #[cfg_attr(feature = "schema", schemars(with = "[usize; 2]"))]
        bodies: [BodyId; 2],
    },
}

/// A body's pose as a joint definition is built against: its frame (origin) and whether it
/// is dynamic.
#[derive(Clone, Copy, Debug)]
pub struct JointFrame {
    /// The body's frame in the world.
    pub frame: Transform,
    /// Whether the body is dynamic.
    pub dynamic: bool,
}

/// Binds `$force` and `$torque` to a joint definition's two threshold fields (by reference,
/// shared or mutable as `$def` is) and evaluates `$body`; a filter joint, which has none,
/// gives `$filter`. One list of the variants for the getter and the builder.
macro_rules! threshold_fields {
    ($def:expr, |$force:ident, $torque:ident| $body:expr, $filter:expr) => {
        match $def {
            JointDef::Revolute {
                force_threshold: $force,
                torque_threshold: $torque,
                ..
            }
            | JointDef::Prismatic {
                force_threshold: $force,
                torque_threshold: $torque,
                ..
            }
            | JointDef::Wheel {
                force_threshold: $force,
                torque_threshold: $torque,
                ..
            }
            | JointDef::Distance {
                force_threshold: $force,
                torque_threshold: $torque,
                ..
            }
            | JointDef::Weld {
                force_threshold: $force,
                torque_threshold: $torque,
                ..
            }
            | JointDef::Motor {
                force_threshold: $force,
                torque_threshold: $torque,
                ..
            } => $body,
            JointDef::Filter { .. } => $filter,
        }
    };
}

impl JointDef {
    /// A plain hinge between `bodies` at `anchor` (world): no limit, motor or spring, the
    /// bodies kept apart.
    pub fn hinge(bodies: [BodyId; 2], anchor: [f32; 2]) -> JointDef {
        JointDef::Revolute {
            force_threshold: f32::INFINITY,
            torque_threshold: f32::INFINITY,
            bodies,
            anchor,
            limit: None,
            motor: None,
            spring: None,
            collide_connected: false,
            anchor_b: None,
        }
    }

    /// The reaction force (N) and torque (N·m) past which the joint reports
    /// [`crate::Event::JointThreshold`] (infinite: never; a filter joint never does).
    pub fn thresholds(&self) -> (f32, f32) {
        threshold_fields!(
            self,
            |force, torque| (*force, *torque),
            (f32::INFINITY, f32::INFINITY)
        )
    }

    /// The same joint reporting past `force` (N) and `torque` (N·m) (see
    /// [`JointDef::thresholds`]; a filter joint has none to set).
    pub fn with_thresholds(mut self, force: f32, torque: f32) -> JointDef {
        threshold_fields!(
            &mut self,
            |force_threshold, torque_threshold| {
                *force_threshold = force;
                *torque_threshold = torque;
            },
            ()
        );
        self
    }

    /// Body A and body B.
    pub fn bodies(&self) -> [BodyId; 2] {
        match self {
            JointDef::Revolute { bodies, .. }
            | JointDef::Prismatic { bodies, .. }
            | JointDef::Wheel { bodies, .. }
            | JointDef::Distance { bodies, .. }
            | JointDef::Weld { bodies, .. }
            | JointDef::Motor { bodies, .. }
            | JointDef::Filter { bodies } => *bodies,
        }
    }

    /// Body A and body B, to change (a definition made for one set of bodies placed on
    /// another: a group of bodies and joints made again elsewhere in a world).
    pub fn bodies_mut(&mut self) -> &mut [BodyId; 2] {
        match self {
            JointDef::Revolute { bodies, .. }
            | JointDef::Prismatic { bodies, .. }
            | JointDef::Wheel { bodies, .. }
            | JointDef::Distance { bodies, .. }
            | JointDef::Weld { bodies, .. }
            | JointDef::Motor { bodies, .. }
            | JointDef::Filter { bodies } => bodies,
        }
    }

    /// The variant's name, as in scene files.
    pub fn name(&self) -> &'static str {
        match self {
            JointDef::Revolute { .. } => "Revolute",
            JointDef::Prismatic { .. } => "Prismatic",
            JointDef::Wheel { .. } => "Wheel",
            JointDef::Distance { .. } => "Distance",
            JointDef::Weld { .. } => "Weld",
            JointDef::Motor { .. } => "Motor",
            JointDef::Filter { .. } => "Filter",
        }
    }

    /// Checks the joint's own fields, and its bodies against `frames` (one per body of the
    /// scene or world, `None` for a free slot). Errors name the joint's `index` and the field.
    pub fn validate(
        &self,
        index: usize,
        frames: &dyn Fn(BodyId) -> Option<JointFrame>,
    ) -> Result<(), SceneError> {
        let name = self.name();
        let err = |field: &str, value: String, allowed: &str| SceneError::Joint {
            index,
            field: format!("{name}.{field}"),
            value,
            allowed: allowed.to_string(),
        };
        let [a, b] = self.bodies();
        let (fa, fb) = match (frames(a), frames(b)) {
            (Some(fa), Some(fb)) => (fa, fb),
            (None, _) | (_, None) => {
                let missing = if frames(a).is_none() { a } else { b };
                return Err(err(
                    "bodies",
                    format!("{} (no body {})", indices([a, b]), describe(missing)),
                    "the indices of two bodies in `bodies`",
                ));
            }
        };
        if a == b {
            return Err(err(
                "bodies",
                indices([a, b]),
                "two different bodies (a joint between a body and itself does nothing)",
            ));
        }
        let (force, torque) = self.thresholds();
        for (field, v) in [("force_threshold", force), ("torque_threshold", torque)] {
            if v.is_nan() || v < 0.0 {
                return Err(err(
                    field,
                    v.to_string(),
                    "a number >= 0 (N or N·m; leave it out for none)",
                ));
            }
        }
        if !fa.dynamic && !fb.dynamic {
            return Err(err(
                "bodies",
                format!("{} (neither is dynamic)", indices([a, b])),
                "at least one dynamic body: a joint moves nothing else",
            ));
        }
        let point = |field: &str, p: [f32; 2]| {
            if p[0].is_finite() && p[1].is_finite() {
                Ok(())
            } else {
                Err(err(
                    field,
                    format!("{p:?}"),
                    "two finite numbers (m, world)",
                ))
            }
        };
        let non_negative = |field: &str, x: f32, unit: &str| {
            if x.is_finite() && x >= 0.0 {
                Ok(())
            } else {
                Err(err(
                    field,
                    x.to_string(),
                    &format!("a finite number >= 0 ({unit})"),
                ))
            }
        };
        let finite = |field: &str, x: f32, unit: &str| {
            if x.is_finite() {
                Ok(())
            } else {
                Err(err(
                    field,
                    x.to_string(),
                    &format!("a finite number ({unit})"),
                ))
            }
        };
        let limit = |field: &str, l: Option<[f32; 2]>, bound: f32, unit: &str| match l {
            Some([lo, hi]) if !(lo.is_finite() && hi.is_finite() && lo <= hi) => Err(err(
                field,
                format!("{:?}", [lo, hi]),
                &format!("[lower, upper] with lower <= upper, both finite ({unit})"),
            )),
            Some([lo, hi]) if lo < -bound || hi > bound => Err(err(
                field,
                format!("{:?}", [lo, hi]),
                &format!("bounds within ±{bound} ({unit})"),
            )),
            _ => Ok(()),
        };
        let spring = |s: &Option<Spring>| match s {
            Some(s) => {
                non_negative("spring.hertz", s.hertz, "Hz")?;
                non_negative("spring.damping_ratio", s.damping_ratio, "1 is critical")
            }
            None => Ok(()),
        };
        let axis = |a: [f32; 2]| {
            let v = Vec2::from(a);
            if v.is_finite() && v.length() > 1e-6 {
                Ok(())
            } else {
                Err(err(
                    "axis",
                    format!("{a:?}"),
                    "a finite, non-zero direction",
                ))
            }
        };
        const ANGLE: f32 = 0.99 * std::f32::consts::PI;
        match self {
            JointDef::Revolute {
                anchor,
                limit: l,
                motor,
                spring: s,
                anchor_b,
                ..
            } => {
                point("anchor", *anchor)?;
                if let Some(p) = anchor_b {
                    point("anchor_b", *p)?;
                }
                limit("limit", *l, ANGLE, "rad; 0.99π at most either way")?;
                if let Some(m) = motor {
                    finite("motor.speed", m.speed, "rad/s")?;
                    non_negative("motor.max_torque", m.max_torque, "N·m")?;
                }
                spring(s)
            }
            JointDef::Prismatic {
                anchor,
                axis: x,
                limit: l,
                motor,
                spring: s,
                ..
            } => {
                point("anchor", *anchor)?;
                axis(*x)?;
                limit("limit", *l, f32::MAX, "m")?;
                if let Some(m) = motor {
                    finite("motor.speed", m.speed, "m/s")?;
                    non_negative("motor.max_force", m.max_force, "N")?;
                }
                spring(s)
            }
            JointDef::Wheel {
                anchor,
                axis: x,
                limit: l,
                motor,
                spring: s,
                ..
            } => {
                point("anchor", *anchor)?;
                axis(*x)?;
                limit("limit", *l, f32::MAX, "m")?;
                if let Some(m) = motor {
                    finite("motor.speed", m.speed, "rad/s")?;
                    non_negative("motor.max_torque", m.max_torque, "N·m")?;
                }
                spring(s)
            }
            JointDef::Distance {
                anchors,
                length,
                limit: l,
                spring: s,
                ..
            } => {
                point("anchors[0]", anchors[0])?;
                point("anchors[1]", anchors[1])?;
                let start = (Vec2::from(anchors[1]) - Vec2::from(anchors[0])).length();
                let rest = length.unwrap_or(start);
                if !(rest.is_finite() && rest >= crate::LINEAR_SLOP) {
                    return Err(err(
                        if length.is_some() {
                            "length"
                        } else {
                            "anchors"
                        },
                        if length.is_some() {
                            rest.to_string()
                        } else {
                            format!("{anchors:?}, {start} m apart")
                        },
                        &format!(
                            "a length of at least {} m (the slop): give `length`, or anchors \
                             apart",
                            crate::LINEAR_SLOP
                        ),
                    ));
                }
                limit("limit", *l, f32::MAX, "m")?;
                if let Some([lo, _]) = l
                    && *lo < 0.0
                {
                    return Err(err("limit", format!("{l:?}"), "lengths >= 0 (m)"));
                }
                spring(s)
            }
            JointDef::Weld {
                anchor,
                linear_hertz,
                angular_hertz,
                linear_damping_ratio,
                angular_damping_ratio,
                ..
            } => {
                point("anchor", *anchor)?;
                non_negative("linear_hertz", *linear_hertz, "Hz; 0 is rigid")?;
                non_negative("angular_hertz", *angular_hertz, "Hz; 0 is rigid")?;
                non_negative(
                    "linear_damping_ratio",
                    *linear_damping_ratio,
                    "1 is critical",
                )?;
                non_negative(
                    "angular_damping_ratio",
                    *angular_damping_ratio,
                    "1 is critical",
                )
            }
            JointDef::Motor {
                linear_offset,
                angular_offset,
                max_force,
                max_torque,
                correction_factor,
                ..
            } => {
                if let Some(o) = linear_offset {
                    point("linear_offset", *o)?;
                }
                if let Some(o) = angular_offset {
                    finite("angular_offset", *o, "rad")?;
                }
                non_negative("max_force", *max_force, "N")?;
                non_negative("max_torque", *max_torque, "N·m")?;
                if !(correction_factor.is_finite() && (0.0..=1.0).contains(correction_factor)) {
                    return Err(err(
                        "correction_factor",
                        correction_factor.to_string(),
                        "a number from 0 to 1 (0.3 is Box2D's)",
                    ));
                }
                Ok(())
            }
            JointDef::Filter { .. } => Ok(()),
        }
    }

    /// Builds the joint between bodies at poses `a` and `b` (the definition validated), with
    /// the rigid rows' `hertz` and `damping_ratio`.
    pub fn build(&self, a: Transform, b: Transform, hertz: f32, damping_ratio: f32) -> Joint {
        let [ia, ib] = self.bodies();
        // The joint frame in the world (anchor, axes) is put into each body's frame.
        let frames = |anchor: Vec2, axes: Rot| {
            let local = |body: Transform| Transform {
                p: body.q.apply_inv(anchor - body.p),
                q: body.q.inv_mul(axes),
            };
            (local(a), local(b))
        };
        let direction = |x: [f32; 2]| {
            let v = Vec2::from(x).normalize();
            Rot { c: v.x, s: v.y }
        };
        let (local_a, local_b, collide_connected, kind) = match self {
            JointDef::Revolute {
                anchor,
                limit,
                motor,
                spring,
                collide_connected,
                anchor_b,
                ..
            } => {
                let (la, _) = frames(Vec2::from(*anchor), Rot::IDENTITY);
                let (_, lb) = frames(Vec2::from(anchor_b.unwrap_or(*anchor)), Rot::IDENTITY);
                let kind = JointKind::Revolute(Revolute {
                    limit: *limit,
                    motor: *motor,
                    spring: *spring,
                    ..Revolute::default()
                });
                (la, lb, *collide_connected, kind)
            }
            JointDef::Prismatic {
                anchor,
                axis,
                limit,
                motor,
                spring,
                collide_connected,
                ..
            } => {
                let (la, lb) = frames(Vec2::from(*anchor), direction(*axis));
                let kind = JointKind::Prismatic(Prismatic {
                    limit: *limit,
                    motor: *motor,
                    spring: *spring,
                    ..Prismatic::default()
                });
                (la, lb, *collide_connected, kind)
            }
            JointDef::Wheel {
                anchor,
                axis,
                limit,
                motor,
                spring,
                collide_connected,
                ..
            } => {
                let (la, lb) = frames(Vec2::from(*anchor), direction(*axis));
                let mut wheel = Wheel {
                    limit: *limit,
                    motor: *motor,
                    ..Wheel::default()
                };
                if spring.is_some() {
                    wheel.spring = *spring;
                }
                (la, lb, *collide_connected, JointKind::Wheel(wheel))
            }
            JointDef::Distance {
                anchors,
                length,
                limit,
                spring,
                collide_connected,
                ..
            } => {
                let (pa, pb) = (Vec2::from(anchors[0]), Vec2::from(anchors[1]));
                let (la, _) = frames(pa, Rot::IDENTITY);
                let (_, lb) = frames(pb, Rot::IDENTITY);
                let kind = JointKind::Distance(Distance {
                    length: length.unwrap_or((pb - pa).length()),
                    limit: *limit,
                    spring: *spring,
                    ..Distance::default()
                });
                (la, lb, *collide_connected, kind)
            }
            JointDef::Weld {
                anchor,
                linear_hertz,
                angular_hertz,
                linear_damping_ratio,
                angular_damping_ratio,
                collide_connected,
                ..
            } => {
                let (la, lb) = frames(Vec2::from(*anchor), Rot::IDENTITY);
                let kind = JointKind::Weld(Weld {
                    linear_hertz: *linear_hertz,
                    angular_hertz: *angular_hertz,
                    linear_damping_ratio: *linear_damping_ratio,
                    angular_damping_ratio: *angular_damping_ratio,
                    ..Weld::default()
                });
                (la, lb, *collide_connected, kind)
            }
            JointDef::Motor {
                linear_offset,
                angular_offset,
                max_force,
                max_torque,
                correction_factor,
                collide_connected,
                ..
            } => {
                // The frames sit at each body's origin.
                let start = a.q.apply_inv(b.p - a.p);
                let kind = JointKind::Motor(Motor {
                    linear_offset: linear_offset.map_or(start, Vec2::from),
                    angular_offset: angular_offset.unwrap_or(a.q.inv_mul(b.q).angle()),
                    max_force: *max_force,
                    max_torque: *max_torque,
                    correction_factor: *correction_factor,
                    ..Motor::default()
                });
                (
                    Transform::IDENTITY,
                    Transform::IDENTITY,
                    *collide_connected,
                    kind,
                )
            }
            JointDef::Filter { .. } => (
                Transform::IDENTITY,
                Transform::IDENTITY,
                false,
                JointKind::Filter,
            ),
        };
        let (force_threshold, torque_threshold) = self.thresholds();
        Joint {
            body_a: ia.index,
            body_b: ib.index,
            local_a,
            local_b,
            collide_connected,
            hertz,
            damping_ratio,
            kind,
            force_threshold,
            torque_threshold,
            user_data: 0,
            step: JointStep::default(),
        }
    }
}

/// Two bodies as a scene file names them: `[a, b]` by index.
fn indices([a, b]: [BodyId; 2]) -> String {
    format!("[{}, {}]", a.index, b.index)
}

/// A body as an error names it: its index, and its generation where it is not a scene's.
fn describe(id: BodyId) -> String {
    if id.generation == 0 {
        id.index.to_string()
    } else {
        id.to_string()
    }
}
