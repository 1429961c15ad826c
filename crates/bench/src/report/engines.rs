//! The engines the report runs and the knob settings it sweeps in each.
//!
//! Every engine builds the case's `SceneDef` the same way `compare` does (see `peers/`); the
//! knobs are set on top: substeps (Box2D's substeps, Rapier's `num_solver_iterations`), contact
//! hertz (contacts against static bodies at twice it in all three), relax passes per substep
//! (Rapier's `num_internal_stabilization_iterations`; Box2D has no such knob) and the push-out
//! speed cap (Box2D's `contactSpeed`, Rapier's `normalized_max_corrective_velocity`).

use anyhow::{Context, Result};
use tumble_physics::{BodyId, SceneDef, StepSettings, World};

use crate::peers::Peer;
use crate::scenes;

/// An engine of the report.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Engine {
    Tumble,
    Box2d,
    Rapier,
}

impl Engine {
    /// The engines this build can run: tumble, and the peers with `--features peers`.
    pub fn available() -> Vec<Engine> {
        if cfg!(feature = "peers") {
            vec![Engine::Tumble, Engine::Box2d, Engine::Rapier]
        } else {
            vec![Engine::Tumble]
        }
    }

    /// Key in the CSV.
    pub fn key(self) -> &'static str {
        match self {
            Engine::Tumble => "tumble",
            Engine::Box2d => "box2d",
            Engine::Rapier => "rapier",
        }
    }

    /// Name in the tables and charts.
    pub fn title(self) -> &'static str {
        match self {
            Engine::Tumble => "tumble",
            Engine::Box2d => "Box2D",
            Engine::Rapier => "Rapier",
        }
    }

    /// The settings swept: every substep count at the defaults; then, at 4 substeps, one knob
    /// at a time (relax passes, a softer contact); then the contact hertz at its clamp (an
    /// eighth of the substep rate) for 8, 12 and 16 substeps, the only way the clamp lets
    /// stiffer contacts act; then the case's `extras`. Settings an engine has no knob for
    /// are left out of its sweep.
    pub fn sweep(self, quick: bool, extras: &[Knobs]) -> Vec<Knobs> {
        let d = Knobs::DEFAULT;
        let substeps: &[u32] = if quick {
            &[1, 4]
        } else {
            &[1, 2, 4, 8, 12, 16]
        };
        let mut out: Vec<Knobs> = substeps
            .iter()
            .map(|&substeps| Knobs { substeps, ..d })
            .collect();
        if quick {
            if self != Engine::Tumble {
                out.retain(|k| k.substeps == 4);
            }
            out.extend(extras.iter().take(1).copied());
        } else {
            for relax in [2, 4] {
                out.push(Knobs { relax, ..d });
            }
            out.push(Knobs { hertz: 15.0, ..d });
            for (substeps, hertz) in [(8, 60.0), (12, 90.0), (16, 120.0)] {
                out.push(Knobs {
                    substeps,
                    hertz,
                    ..d
                });
            }
            out.extend(extras.iter().copied());
        }
        out.retain(|k| self.supports(k));
        out
    }

    /// Whether the engine has the knobs this setting turns.
    fn supports(self, k: &Knobs) -> bool {
        let d = Knobs::DEFAULT;
        match self {
            Engine::Tumble => true,
            // Neither peer has more than one restitution pass.
            // Box2D solves a manifold's points in turn, whatever tumble's default; its rows
            // are those of tumble's default of that knob.
            Engine::Box2d => {
                k.relax == d.relax
                    && k.restitution_passes == d.restitution_passes
                    && k.together == d.together
                    && k.impacts == d.impacts
            }
            // Rapier has no restitution threshold: a contact with restitution >= 1 always
            // bounces, others bounce on their first step of contact. Its joints' locked rows
            // are rigid: no joint hertz.
            Engine::Rapier => {
                k.threshold == d.threshold
                    && k.restitution_passes == d.restitution_passes
                    && k.joint_hertz == d.joint_hertz
                    && k.together == d.together
                    && k.impacts == d.impacts
            }
        }
    }

    /// What the knobs are called in this engine, for the report's settings section.
    pub fn knob_names(self) -> &'static str {
        match self {
            Engine::Tumble => {
                "`step(dt, substeps)`; `StepSettings::{relax_iterations, contact_hertz, max_push_speed, restitution_threshold, restitution_iterations, solve_points_together, impacts_bounce}`"
            }
            Engine::Box2d => {
                "`b2World_Step(dt, subStepCount)`; `b2WorldDef::{contactHertz, contactSpeed, restitutionThreshold}` (no relax knob: Box2D always runs one relax pass per substep)"
            }
            Engine::Rapier => {
                "`IntegrationParameters::{num_solver_iterations, num_internal_stabilization_iterations, contact_softness (static: twice), normalized_max_corrective_velocity}` (no restitution threshold: a contact of restitution 1 always bounces)"
            }
        }
    }
}

/// One point of the sweep.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Knobs {
    /// Substeps per step (Rapier: `num_solver_iterations`).
    pub substeps: u32,
    /// Relax passes per substep (Rapier: stabilization iterations; Box2D: always 1).
    pub relax: u32,
    /// Contact stiffness (Hz); twice it against static bodies.
    pub hertz: f32,
    /// Push-out speed cap (m/s).
    pub push: f32,
    /// Approach speed below which restitution is not applied (m/s).
    pub threshold: f32,
    /// Restitution passes at the end of a step (tumble only; Box2D and Rapier: 1).
    pub restitution_passes: u32,
    /// Stiffness of the joints' rigid rows (Hz; the scene's `solver.joint_hertz`; tumble and
    /// Box2D: clamped to a quarter of the substep rate; Rapier's joints are rigid).
    pub joint_hertz: f32,
    /// A manifold's two points solved together (tumble only, and its default:
    /// `StepSettings::solve_points_together`; off is Box2D's rule, the points in turn).
    pub together: bool,
    /// Impacts bounce as restitution says: the threshold only for contacts already pushing,
    /// and passes until the bounces hold (tumble only, and its default:
    /// `StepSettings::impacts_bounce`; off is Box2D's rule).
    pub impacts: bool,
}

impl Knobs {
    /// tumble's defaults, which are Box2D's (and Rapier 0.36's) but for a manifold's points
    /// solved together.
    pub const DEFAULT: Knobs = Knobs {
        substeps: 4,
        relax: 1,
        hertz: 30.0,
        push: 3.0,
        threshold: 1.0,
        restitution_passes: 1,
        joint_hertz: 60.0,
        together: true,
        impacts: true,
    };

    /// "4 sub", "4 sub, 2 relax", "4 sub, 15 Hz", "4 sub, push 1 m/s": the substeps and
    /// whatever differs from the defaults.
    pub fn label(&self) -> String {
        let d = Knobs::DEFAULT;
        let mut s = format!("{} sub", self.substeps);
        if self.relax != d.relax {
            s.push_str(&format!(", {} relax", self.relax));
        }
        if self.hertz != d.hertz {
            s.push_str(&format!(", {} Hz", self.hertz));
        }
        if self.push != d.push {
            s.push_str(&format!(", push {} m/s", self.push));
        }
        if self.threshold != d.threshold {
            s.push_str(&format!(", threshold {} m/s", self.threshold));
        }
        if self.restitution_passes != d.restitution_passes {
            s.push_str(&format!(", {} restitution passes", self.restitution_passes));
        }
        if self.joint_hertz != d.joint_hertz {
            s.push_str(&format!(", joints {} Hz", self.joint_hertz));
        }
        if self.together != d.together {
            s.push_str(if self.together {
                ", points together"
            } else {
                ", points in turn"
            });
        }
        if self.impacts != d.impacts {
            s.push_str(if self.impacts {
                ", impacts bounce"
            } else {
                ", Box2D's restitution"
            });
        }
        s
    }

    /// A short label for chart points: "4", "r2", "15Hz", "16/120Hz", "p1", "t0".
    pub fn short(&self) -> String {
        let d = Knobs::DEFAULT;
        let prefix = if self.substeps == d.substeps {
            String::new()
        } else {
            format!("{}/", self.substeps)
        };
        if self.together != d.together {
            format!("{prefix}{}", if self.together { "pt" } else { "it" })
        } else if self.impacts != d.impacts {
            format!("{prefix}{}", if self.impacts { "ib" } else { "b2r" })
        } else if self.joint_hertz != d.joint_hertz {
            format!("{prefix}j{}Hz", self.joint_hertz)
        } else if self.relax != d.relax {
            format!("{prefix}r{}", self.relax)
        } else if self.hertz != d.hertz {
            format!("{prefix}{}Hz", self.hertz)
        } else if self.push != d.push {
            format!("{prefix}p{}", self.push)
        } else if self.restitution_passes != d.restitution_passes {
            format!("{prefix}t{}e{}", self.threshold, self.restitution_passes)
        } else if self.threshold != d.threshold {
            format!("{prefix}t{}", self.threshold)
        } else {
            format!("{}", self.substeps)
        }
    }

    /// Nominal work per step: solver passes per step (substeps × (1 + relax)). Breaks ties
    /// between points whose measured ms/step are within noise of each other.
    pub fn work(&self) -> u32 {
        self.substeps * (1 + self.relax)
    }

    /// Whether these are the defaults.
    pub fn is_default(&self) -> bool {
        *self == Knobs::DEFAULT
    }
}

/// Builds the scene in `engine` with `knobs`, on `threads` workers.
pub fn build(
    engine: Engine,
    scene: &SceneDef,
    knobs: &Knobs,
    threads: usize,
) -> Result<Box<dyn Peer>> {
    let mut scene_k = scene.clone();
    scene_k.substeps = knobs.substeps;
    if knobs.joint_hertz != Knobs::DEFAULT.joint_hertz {
        scene_k.solver.joint_hertz = Some(knobs.joint_hertz);
    }
    match engine {
        Engine::Tumble => Ok(Box::new(TumbleSim::new(&scene_k, knobs, threads)?)),
        #[cfg(feature = "peers")]
        Engine::Box2d => {
            let settings = settings_of(&scene_k, knobs)?;
            Ok(Box::new(crate::peers::box2d::Box2d::new(
                &scene_k, &settings, threads,
            )?))
        }
        #[cfg(feature = "peers")]
        Engine::Rapier => {
            let d = Knobs::DEFAULT;
            let tuning = crate::peers::rapier::Tuning {
                contact_hertz: (knobs.hertz != d.hertz).then_some(knobs.hertz),
                stabilization_iterations: (knobs.relax != d.relax).then_some(knobs.relax as usize),
                max_corrective_velocity: (knobs.push != d.push).then_some(knobs.push),
            };
            Ok(Box::new(crate::peers::rapier::Rapier::tuned(
                &scene_k, threads, &tuning,
            )?))
        }
        #[cfg(not(feature = "peers"))]
        other => anyhow::bail!(
            "{} needs a tumble-bench built with `--features peers`",
            other.title()
        ),
    }
}

/// tumble's settings for a scene with the knobs applied (what Box2D is told too).
#[cfg(feature = "peers")]
fn settings_of(scene: &SceneDef, knobs: &Knobs) -> Result<StepSettings> {
    let mut empty = scene.clone();
    empty.bodies.clear();
    empty.joints.clear();
    let mut settings = *World::from_scene(&empty, &scenes::limits())?.settings();
    apply(&mut settings, knobs);
    Ok(settings)
}

fn apply(settings: &mut StepSettings, knobs: &Knobs) {
    settings.relax_iterations = knobs.relax;
    settings.contact_hertz = knobs.hertz;
    settings.max_push_speed = knobs.push;
    settings.restitution_threshold = knobs.threshold;
    settings.restitution_iterations = knobs.restitution_passes;
    settings.solve_points_together = knobs.together;
    settings.impacts_bounce = knobs.impacts;
}

/// tumble behind the peers' trait, so one loop runs and times every engine.
struct TumbleSim {
    world: World,
    dt: f32,
    substeps: u32,
}

impl TumbleSim {
    fn new(scene: &SceneDef, knobs: &Knobs, threads: usize) -> Result<TumbleSim> {
        let mut world = World::from_scene(scene, &scenes::limits())
            .with_context(|| format!("{}: cannot build the tumble world", scene.name))?;
        world.set_thread_count(threads);
        apply(world.settings_mut(), knobs);
        world
            .settings()
            .validate()
            .with_context(|| format!("{}: the setting {}", scene.name, knobs.label()))?;
        Ok(TumbleSim {
            world,
            dt: scene.dt,
            substeps: knobs.substeps,
        })
    }
}

impl Peer for TumbleSim {
    fn step(&mut self) -> Result<()> {
        self.world.step(self.dt, self.substeps);
        Ok(())
    }

    fn pose(&mut self, index: usize) -> Result<[f32; 3]> {
        // The frame's origin, as the peers report it (the centre of mass for one shape).
        let b = self.world.body(BodyId::scene(index))?;
        Ok([b.origin.x, b.origin.y, b.angle])
    }

    fn velocity(&mut self, index: usize) -> Result<[f32; 3]> {
        let b = self.world.body(BodyId::scene(index))?;
        Ok([b.linear_velocity.x, b.linear_velocity.y, b.angular_velocity])
    }

    fn non_finite_bodies(&mut self) -> u64 {
        self.world.non_finite_bodies()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sweeps_cover_substeps_and_each_knob_around_the_defaults() {
        let push = [Knobs {
            push: 1.0,
            ..Knobs::DEFAULT
        }];
        let t = Engine::Tumble.sweep(false, &[]);
        let subs: Vec<u32> = t
            .iter()
            .filter(|k| k.relax == 1 && k.hertz == 30.0)
            .map(|k| k.substeps)
            .collect();
        assert_eq!(subs, vec![1, 2, 4, 8, 12, 16]);
        assert!(t.iter().any(|k| k.relax == 4 && k.substeps == 4));
        assert!(t.iter().any(|k| k.hertz == 15.0 && k.substeps == 4));
        assert!(t.iter().any(|k| k.hertz == 120.0 && k.substeps == 16));
        assert!(!Engine::Box2d.sweep(false, &[]).iter().any(|k| k.relax != 1));
        assert!(
            Engine::Rapier
                .sweep(false, &push)
                .iter()
                .any(|k| k.push == 1.0)
        );
        let threshold = [Knobs {
            threshold: 0.0,
            ..Knobs::DEFAULT
        }];
        assert!(
            !Engine::Rapier
                .sweep(false, &threshold)
                .iter()
                .any(|k| k.threshold == 0.0)
        );
        assert!(
            Engine::Box2d
                .sweep(false, &threshold)
                .iter()
                .any(|k| k.threshold == 0.0)
        );
        assert_eq!(Knobs::DEFAULT.label(), "4 sub");
        assert_eq!(
            Knobs {
                hertz: 15.0,
                ..Knobs::DEFAULT
            }
            .label(),
            "4 sub, 15 Hz"
        );
    }
}
