//! Small 2D math on top of glam: rotations as (cos, sin), rigid transforms, cross products.
//!
//! No fused multiply-add anywhere: results must be bit-identical on every thread count and
//! every build, so each operation is a plain multiply or add.

use glam::Vec2;
use serde::{Deserialize, Serialize};

/// A&S 4.4.49's a2 to a16, for [`atan2`] and its eight-lane twin (`solver::lanes::atan2`).
// The coefficients as A&S print them (f32 rounds them), so they can be checked against it.
#[allow(clippy::excessive_precision)]
pub(crate) const ATAN_COEFFICIENTS: [f32; 8] = [
    -0.333_331_452_8,
    0.199_935_508_5,
    -0.142_088_994_4,
    0.106_562_639_3,
    -0.075_289_64,
    0.042_909_613_8,
    -0.016_165_736_7,
    0.002_866_225_7,
];

/// The angle of the point (x, y) from the x axis, in [-π, π]; 0 at the origin. The arctangent
/// on [0, 1] is the minimax polynomial of Abramowitz and Stegun 4.4.49 (error ≤ 2·10⁻⁸ rad in
/// exact arithmetic; measured within 3·10⁻⁷ rad of f64's in f32, below), folded to the full
/// circle by the octant symmetries. It is plain multiplies and adds: the same bits on every
/// platform and build (the C library's `atan2f` differs between them), and about three times
/// cheaper, which the joints' angle rows, solved eight times a step, feel.
#[inline]
pub fn atan2(y: f32, x: f32) -> f32 {
    use std::f32::consts::{FRAC_PI_2, PI};
    let (ax, ay) = (x.abs(), y.abs());
    let (small, large) = if ay > ax { (ax, ay) } else { (ay, ax) };
    if large == 0.0 {
        // The origin. A NaN passes by and makes the result NaN.
        return 0.0;
    }
    let t = small / large;
    let t2 = t * t;
    // A&S 4.4.49: atan t = t (1 + a2 t² + a4 t⁴ + ... + a16 t¹⁶), 0 ≤ t ≤ 1, the sum in
    // t² evaluated by Estrin's scheme (pairs, then pairs of pairs): a short chain of
    // dependent operations, where Horner's rule is one long one.
    let s2 = t2 * t2;
    let s4 = s2 * s2;
    let a = ATAN_COEFFICIENTS;
    let e0 = a[0] + a[1] * t2;
    let e1 = a[2] + a[3] * t2;
    let e2 = a[4] + a[5] * t2;
    let e3 = a[6] + a[7] * t2;
    let p = (e0 + e1 * s2) + (e2 + e3 * s2) * s4;
    let mut r = t + t * (p * t2);
    if ay > ax {
        r = FRAC_PI_2 - r;
    }
    if x < 0.0 {
        r = PI - r;
    }
    if y < 0.0 { -r } else { r }
}

/// A rotation stored as its cosine and sine.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Rot {
    /// Cosine of the angle.
    pub c: f32,
    /// Sine of the angle.
    pub s: f32,
}

impl Default for Rot {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl Rot {
    /// No rotation.
    pub const IDENTITY: Rot = Rot { c: 1.0, s: 0.0 };

    /// The rotation by `angle` radians.
    pub fn from_angle(angle: f32) -> Self {
        let (s, c) = angle.sin_cos();
        Rot { c, s }
    }

    /// The angle in [-π, π] (this module's `atan2`).
    #[inline]
    pub fn angle(self) -> f32 {
        atan2(self.s, self.c)
    }

    /// Rotates a vector.
    #[inline]
    pub fn apply(self, v: Vec2) -> Vec2 {
        Vec2::new(self.c * v.x - self.s * v.y, self.s * v.x + self.c * v.y)
    }

    /// Rotates a vector by the inverse rotation.
    #[inline]
    pub fn apply_inv(self, v: Vec2) -> Vec2 {
        Vec2::new(self.c * v.x + self.s * v.y, -self.s * v.x + self.c * v.y)
    }

    /// `self * other`: the rotation by `other`, then by `self`.
    #[inline]
    pub fn then_from(self, other: Rot) -> Rot {
        Rot {
            c: self.c * other.c - self.s * other.s,
            s: self.s * other.c + self.c * other.s,
        }
    }

    /// `self⁻¹ * other`.
    #[inline]
    pub fn inv_mul(self, other: Rot) -> Rot {
        Rot {
            c: self.c * other.c + self.s * other.s,
            s: self.c * other.s - self.s * other.c,
        }
    }

    /// Back to unit length (rotations drift under repeated first-order integration).
    #[inline]
    pub fn normalize(self) -> Rot {
        let mag = (self.c * self.c + self.s * self.s).sqrt();
        let inv = if mag > 0.0 { 1.0 / mag } else { 0.0 };
        Rot {
            c: self.c * inv,
            s: self.s * inv,
        }
    }

    /// Advances the rotation by a small angle `delta` with a first-order step, then
    /// normalises. Box2D's `b2IntegrateRotation`: cheaper than sin/cos and exact for the
    /// direction of motion; the angle error is O(delta³) per substep.
    #[inline]
    pub fn integrate(self, delta: f32) -> Rot {
        Rot {
            c: self.c - delta * self.s,
            s: self.s + delta * self.c,
        }
        .normalize()
    }
}

/// A rigid transform: rotation then translation.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Transform {
    /// Translation (the body's centre of mass).
    pub p: Vec2,
    /// Rotation.
    pub q: Rot,
}

impl Transform {
    /// No rotation, no translation.
    pub const IDENTITY: Transform = Transform {
        p: Vec2::ZERO,
        q: Rot::IDENTITY,
    };

    /// `self * local`: a frame given in `self`'s frame, expressed in the world.
    #[inline]
    pub fn compose(self, local: Transform) -> Transform {
        Transform {
            p: self.apply(local.p),
            q: local.q.then_from(self.q),
        }
    }

    /// Maps a point from the local frame to the world.
    #[inline]
    pub fn apply(self, v: Vec2) -> Vec2 {
        self.q.apply(v) + self.p
    }

    /// Maps a world point into the local frame.
    #[inline]
    pub fn apply_inv(self, v: Vec2) -> Vec2 {
        self.q.apply_inv(v - self.p)
    }

    /// `self⁻¹ * other`: `other` expressed in `self`'s frame.
    #[inline]
    pub fn inv_mul(self, other: Transform) -> Transform {
        Transform {
            q: self.q.inv_mul(other.q),
            p: self.q.apply_inv(other.p - self.p),
        }
    }
}

/// `x` held within ±`max`, as `f32::clamp(-max, max)` holds it for a bound that is a number
/// ≥ 0, without its panic on a negative or NaN one (a motor's torque set between steps through
/// `World::joint_kind_mut` is not checked; a NaN impulse must reach the step's NaN guard):
/// below the least, then above the most, the selects the eight-lane kernels make.
#[inline]
pub(crate) fn clamp_within(x: f32, max: f32) -> f32 {
    let x = if x < -max { -max } else { x };
    if x > max { max } else { x }
}

/// 2D cross product of two vectors (a scalar).
#[inline]
pub fn cross(a: Vec2, b: Vec2) -> f32 {
    a.x * b.y - a.y * b.x
}

/// Cross product of a scalar (an angular velocity) with a vector: `w × r`.
#[inline]
pub fn cross_sv(s: f32, v: Vec2) -> Vec2 {
    Vec2::new(-s * v.y, s * v.x)
}

/// The vector turned a quarter clockwise: `(y, -x)`.
#[inline]
pub fn right_perp(v: Vec2) -> Vec2 {
    Vec2::new(v.y, -v.x)
}

/// Dot product written out, so no build fuses it.
#[inline]
pub fn dot(a: Vec2, b: Vec2) -> f32 {
    a.x * b.x + a.y * b.y
}

/// Unit vector and length; zero vector and 0 for a zero input.
#[inline]
pub fn normalize_and_length(v: Vec2) -> (Vec2, f32) {
    let len = (v.x * v.x + v.y * v.y).sqrt();
    if len < f32::EPSILON {
        (Vec2::ZERO, 0.0)
    } else {
        (v * (1.0 / len), len)
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn atan2_is_within_3e_7_of_f64_all_round_the_circle() {
        // 2^20 points round the circle, on the unit circle and far from it, plus the axes.
        let mut worst = 0.0f64;
        for k in 0..(1 << 20) {
            let a = -std::f64::consts::PI
                + (k as f64 + 0.5) * std::f64::consts::TAU / f64::from(1 << 20);
            for r in [1.0f64, 1e-3, 7e4] {
                let (y, x) = ((a.sin() * r) as f32, (a.cos() * r) as f32);
                let exact = f64::from(y).atan2(f64::from(x));
                worst = worst.max((f64::from(atan2(y, x)) - exact).abs());
            }
        }
        assert!(worst < 3e-7, "worst error {worst:e} rad");
        for (y, x, exact) in [
            (0.0f32, 1.0f32, 0.0f32),
            (1.0, 0.0, std::f32::consts::FRAC_PI_2),
            (0.0, -1.0, std::f32::consts::PI),
            (-1.0, 0.0, -std::f32::consts::FRAC_PI_2),
            (1.0, 1.0, std::f32::consts::FRAC_PI_4),
            (0.0, 0.0, 0.0),
        ] {
            assert!((atan2(y, x) - exact).abs() <= 2e-7, "atan2({y}, {x})");
        }
        assert!(atan2(f32::NAN, 1.0).is_nan() && atan2(1.0, f32::NAN).is_nan());
    }

    use super::*;

    #[test]
    fn rotation_round_trip() {
        let q = Rot::from_angle(0.7);
        let v = Vec2::new(1.5, -2.0);
        let back = q.apply_inv(q.apply(v));
        // Two rotations in f32: each component off by a few ulps of |v| ~ 2.5.
        assert!((back - v).length() < 1e-6);
        assert!((q.angle() - 0.7).abs() < 1e-6);
    }

    #[test]
    fn integrate_rotation_matches_angle_for_small_steps() {
        let mut q = Rot::IDENTITY;
        for _ in 0..240 {
            q = q.integrate(1.0 / 240.0);
        }
        // First-order steps of 1/240 rad lag the true angle by ~h²/3 per step (tan⁻¹ series):
        // 240 · (1/240)³/3 ≈ 6e-6 rad in all.
        assert!((q.angle() - 1.0).abs() < 2e-5, "{}", q.angle());
    }

    #[test]
    fn transform_inverse() {
        let a = Transform {
            p: Vec2::new(1.0, 2.0),
            q: Rot::from_angle(0.3),
        };
        let b = Transform {
            p: Vec2::new(-3.0, 0.5),
            q: Rot::from_angle(-1.1),
        };
        let rel = a.inv_mul(b);
        let p = Vec2::new(0.25, 0.75);
        let via = a.apply(rel.apply(p));
        assert!((via - b.apply(p)).length() < 1e-5);
    }
}
