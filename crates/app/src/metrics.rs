//! The error a scene's run has bought so far, measured from the state after every frame's
//! steps, for the solver panel to show beside ms/step: move the substeps or contact-hertz
//! slider and watch both change. The hard cases of `tumble-bench report`
//! (docs/accuracy/REPORT.md) get their own metric and pass bound; every scene gets the
//! deepest overlap and the kinetic energy.

use glam::Vec2;
use tumble_physics::{BodyId, BodyKind, SceneDef, World};

/// Which error a scene is judged by.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Case {
    /// A structure that should stand: the largest distance any dynamic body has moved from
    /// where it started (m), bounded as the report bounds its stacks and pyramids.
    Displacement {
        /// Pass bound (m).
        bound: f64,
    },
    /// A closed, frictionless, elastic gas: the largest |E − E₀| / E₀ of the kinetic energy.
    EnergyDrift {
        /// Pass bound (a fraction).
        bound: f64,
    },
    /// Boxes spawned overlapping: the fastest any body moved while they separate (m/s).
    PeakSpeed {
        /// Pass bound (m/s).
        bound: f64,
    },
    /// No case-specific metric.
    #[default]
    None,
}

impl Case {
    /// The case of a scene, by the name the report gives it; the bounds are the pass
    /// criteria that `tests/tests/accuracy.rs` and `stability.rs` assert.
    pub fn of(scene: &str) -> Case {
        match scene {
            "vertical_stack" | "pyramid" | "large_pyramid" | "pyramid_200"
            | "mass_ratio_columns" | "far_from_origin" | "card_house" | "arch" => {
                Case::Displacement { bound: 0.1 }
            }
            "elastic_box" => Case::EnergyDrift { bound: 0.05 },
            "overlap_recovery" => Case::PeakSpeed { bound: 3.0 },
            _ => Case::None,
        }
    }
}

/// Measured error of the current run.
#[derive(Clone, Debug, Default)]
pub struct Metrics {
    /// The scene's case.
    pub case: Case,
    /// Where each body started (for [`Case::Displacement`]).
    start: Vec<Vec2>,
    /// Kinetic energy at the start (J).
    energy0: f64,
    /// Kinetic energy now (J).
    pub energy: f64,
    /// Deepest overlap of any touching pair now (m, ≥ 0).
    pub deepest_overlap: f32,
    /// The case's metric now.
    pub value: f64,
    /// The case's metric at its worst over the run (what the bound applies to).
    pub worst: f64,
}

impl Metrics {
    /// Metrics for a run of `scene` starting from `world` (as built from the scene).
    pub fn new(scene: &SceneDef, world: &World) -> Metrics {
        let case = Case::of(&scene.name);
        let start = match case {
            // By the scene's index, which is the body's id's (`BodyId::scene`).
            Case::Displacement { .. } => world.bodies().map(|(_, b)| b.position).collect(),
            _ => Vec::new(),
        };
        let energy0 = world.kinetic_energy();
        let mut m = Metrics {
            case,
            start,
            energy0,
            ..Metrics::default()
        };
        m.measure(world);
        m.worst = 0.0;
        m
    }

    /// Measures the world now; O(bodies + contacts), once a frame.
    pub fn measure(&mut self, world: &World) {
        self.energy = world.kinetic_energy();
        self.deepest_overlap = world
            .contacts()
            .flat_map(|c| c.manifold.points().iter().map(|p| -p.separation))
            .fold(0.0f32, f32::max);
        self.value = match self.case {
            // The scene's bodies that are still there (a body the user dropped later may
            // have taken a removed one's slot, under a new generation).
            Case::Displacement { .. } => (0..self.start.len())
                .filter_map(|i| world.body(BodyId::scene(i)).ok().map(|b| (i, b)))
                .filter(|(_, b)| b.kind == BodyKind::Dynamic)
                .map(|(i, b)| f64::from((b.position - self.start[i]).length()))
                .fold(0.0, f64::max),
            Case::EnergyDrift { .. } if self.energy0 > 0.0 => {
                (self.energy / self.energy0 - 1.0).abs()
            }
            Case::PeakSpeed { .. } => world
                .bodies()
                .map(|(_, b)| f64::from(b.linear_velocity.length()))
                .fold(0.0, f64::max),
            _ => 0.0,
        };
        self.worst = self.worst.max(self.value);
    }

    /// The case's row for the panel: (name, value now and worst, whether the worst passes).
    pub fn case_row(&self) -> Option<(&'static str, String, bool)> {
        let (name, text, bound) = match self.case {
            Case::Displacement { bound } => (
                "largest displacement",
                format!(
                    "{:.3} m (worst {:.3}, pass < {bound})",
                    self.value, self.worst
                ),
                bound,
            ),
            Case::EnergyDrift { bound } => (
                "energy drift",
                format!(
                    "{:.1}% (worst {:.1}%, pass < {:.0}%)",
                    100.0 * self.value,
                    100.0 * self.worst,
                    100.0 * bound
                ),
                bound,
            ),
            Case::PeakSpeed { bound } => (
                "peak speed",
                format!("{:.2} m/s (pass < {bound})", self.worst),
                bound,
            ),
            Case::None => return None,
        };
        Some((name, text, self.worst < bound))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(name: &str, steps: u32) -> Metrics {
        run_with(name, steps, |_| {})
    }

    /// [`run`] with the step settings changed by `tweak` first.
    fn run_with(
        name: &str,
        steps: u32,
        tweak: impl Fn(&mut tumble_physics::StepSettings),
    ) -> Metrics {
        let scene = tumble_scene::builtin::build(name).expect("built-in");
        let mut world = crate::sim::build_world(&scene).unwrap();
        world.set_thread_count(1);
        tweak(world.settings_mut());
        let mut m = Metrics::new(&scene, &world);
        for _ in 0..steps {
            world.step(scene.dt, scene.substeps);
            m.measure(&world);
        }
        m
    }

    #[test]
    fn a_standing_pyramid_passes_and_its_overlap_is_millimetres() {
        // 3 s of the 20-row pyramid at the defaults: the report measures 3 cm of settling
        // after 10 s and 4 mm of overlap; 0.1 m is the pass bound.
        let m = run("pyramid", 180);
        let (name, _, pass) = m.case_row().unwrap();
        assert_eq!(name, "largest displacement");
        assert!(pass && m.worst > 0.001, "worst {}", m.worst);
        // Soft contacts under 20 rows of load overlap by millimetres, never centimetres.
        assert!(m.deepest_overlap > 1e-4 && m.deepest_overlap < 0.02);
        // Settled: what motion is left is a jitter of far under a joule.
        assert!(m.energy < 1.0, "energy {}", m.energy);
    }

    #[test]
    fn the_elastic_box_reports_its_energy_loss() {
        // The report: at the defaults (impacts bounce as their restitution says) the gas
        // loses 1.8% of its energy in 60 s, 1.5% in the first 10 s, so the row says it
        // passes; under Box2D's rule 91% in 60 s, after 10 s well over the 5% bound already,
        // so the row says it fails.
        let m = run("elastic_box", 600);
        let (_, text, pass) = m.case_row().unwrap();
        assert!(pass, "{text}");
        assert!(m.worst > 1e-4 && m.worst < 0.05, "worst {}", m.worst);
        let m = run_with("elastic_box", 600, |s| s.impacts_bounce = false);
        let (_, text, pass) = m.case_row().unwrap();
        assert!(!pass, "{text}");
        assert!(m.worst > 0.05 && m.worst <= 1.0, "worst {}", m.worst);
    }

    #[test]
    fn overlap_recovery_tracks_the_peak_speed() {
        let m = run("overlap_recovery", 120);
        // The report measures 3.5 m/s at the defaults, over the 3 m/s bound; the peak is a
        // real separation speed, not zero and not an explosion.
        assert!(m.worst > 0.5 && m.worst < 10.0, "peak {}", m.worst);
        assert_eq!(Case::of("falling_circles"), Case::None);
    }
}
