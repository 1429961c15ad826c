//! Soft constraints' spring-damper coefficients, shared by contacts and joints.

/// Spring-damper coefficients of a soft constraint for one substep length
/// (Box2D `b2MakeSoft`; Catto, "Solver2D", 2024, soft step).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Softness {
    /// How fast overlap is pushed out (1/s).
    pub bias_rate: f32,
    /// Weight of the velocity error.
    pub mass_scale: f32,
    /// Weight of the accumulated impulse (the spring's relaxation).
    pub impulse_scale: f32,
}

impl Softness {
    /// Implicit Euler on a spring of `hertz` and damping ratio `zeta` over a substep `h`.
    /// A hertz of 0 is rigid: no position bias, the full velocity correction (Box2D's
    /// `b2MakeSoft`; a joint's rigid rows at `joint_hertz` 0).
    pub fn new(hertz: f32, zeta: f32, h: f32) -> Softness {
        if hertz == 0.0 {
            return Softness {
                bias_rate: 0.0,
                mass_scale: 1.0,
                impulse_scale: 0.0,
            };
        }
        let omega = 2.0 * std::f32::consts::PI * hertz;
        let a1 = 2.0 * zeta + h * omega;
        let a2 = h * omega * a1;
        let a3 = 1.0 / (1.0 + a2);
        Softness {
            bias_rate: omega / a1,
            mass_scale: a2 * a3,
            impulse_scale: a3,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn softness_matches_box2d_defaults() {
        // docs/soft_step.md 2.3 table: 30 Hz, ζ 10, h = 1/240 gives biasRate 9.069/s,
        // massScale 0.9423, impulseScale 0.0577 (4 significant figures there).
        let s = Softness::new(30.0, 10.0, 1.0 / 240.0);
        assert!((s.bias_rate - 9.069).abs() < 5e-3, "{}", s.bias_rate);
        assert!((s.mass_scale - 0.9423).abs() < 5e-4);
        assert!((s.impulse_scale - 0.0577).abs() < 5e-4);
        // The two scales always sum to one.
        assert!((s.mass_scale + s.impulse_scale - 1.0).abs() < 1e-6);
        let st = Softness::new(60.0, 10.0, 1.0 / 240.0);
        assert!((st.bias_rate - 17.48).abs() < 1e-2);
    }
}
