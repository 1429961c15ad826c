//! A scene in Rapier2D (feature `parallel`).
//!
//! Mapping: each tumble body is one rigid body with one collider: boxes are cuboids, other
//! polygons convex polylines of tumble's centroid-recentred vertices (counter-clockwise, as
//! the scene requires), circles balls. Friction: each collider gets its body's coefficient and
//! `CoefficientCombineRule::GeometricMean`, which is exactly tumble's `sqrt(a * b)` for every
//! pair (equal coefficients or not). Restitution: `CoefficientCombineRule::Max`, tumble's rule.
//! `dt` is the scene's; `num_solver_iterations` = the scene's substeps (Rapier's substeps);
//! sleeping off on every body; CCD off (`max_ccd_substeps = 0`, the world-wide switch, and no
//! body asks for it); all other integration parameters are Rapier's defaults. The step runs
//! inside a rayon pool of `threads` threads.

use anyhow::{Context, Result};
use rapier2d::prelude::*;
use rapier2d::rayon;
use tumble_physics::{BodyKind, SceneDef, Shape, ShapeDef as TumbleShape};

use super::Peer;

/// A Rapier world holding a tumble scene.
pub struct Rapier {
    world: PhysicsWorld,
    handles: Vec<RigidBodyHandle>,
    pool: rayon::ThreadPool,
}

/// Knobs of Rapier's solver that the accuracy report sweeps; `None` keeps Rapier's default.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Tuning {
    /// Contact spring frequency (Hz) against dynamic bodies; contacts with a fixed body get
    /// twice it, as Rapier's defaults (30 and 60 Hz) and tumble do.
    pub contact_hertz: Option<f32>,
    /// `num_internal_stabilization_iterations`: Rapier's unbiased passes per substep, the
    /// counterpart of tumble's and Box2D's relax pass.
    pub stabilization_iterations: Option<usize>,
    /// `normalized_max_corrective_velocity` (m/s): how fast overlap is pushed out.
    pub max_corrective_velocity: Option<f32>,
}

/// rapier2d's crate version.
pub fn version() -> &'static str {
    rapier2d::VERSION
}

impl Rapier {
    /// Builds the scene.
    pub fn new(scene: &SceneDef, threads: usize) -> Result<Rapier> {
        Rapier::tuned(scene, threads, &Tuning::default())
    }

    /// Builds the scene with some of Rapier's solver knobs set (see [`Tuning`]).
    pub fn tuned(scene: &SceneDef, threads: usize, tuning: &Tuning) -> Result<Rapier> {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .thread_name(|i| format!("rapier-bench-{i}"))
            .build()
            .context("cannot start Rapier's thread pool")?;
        let mut world = PhysicsWorld {
            gravity: Vector::new(scene.gravity[0], scene.gravity[1]),
            ..PhysicsWorld::default()
        };
        let params = &mut world.integration_parameters;
        params.dt = scene.dt;
        params.num_solver_iterations = scene.substeps as usize;
        params.max_ccd_substeps = 0;
        if let Some(hertz) = tuning.contact_hertz {
            params.contact_softness.natural_frequency = hertz;
            params.static_contact_softness.natural_frequency = 2.0 * hertz;
        }
        if let Some(n) = tuning.stabilization_iterations {
            params.num_internal_stabilization_iterations = n;
        }
        if let Some(v) = tuning.max_corrective_velocity {
            params.normalized_max_corrective_velocity = v;
        }
        let mut handles = Vec::with_capacity(scene.bodies.len());
        for (i, b) in scene.bodies.iter().enumerate() {
            let builder = match b.kind {
                BodyKind::Static => RigidBodyBuilder::fixed(),
                BodyKind::Dynamic => RigidBodyBuilder::dynamic(),
                BodyKind::Kinematic => RigidBodyBuilder::kinematic_velocity_based(),
            };
            let mut builder = builder
                .translation(Vector::new(b.position[0], b.position[1]))
                .rotation(b.angle)
                .linvel(Vector::new(b.linear_velocity[0], b.linear_velocity[1]))
                .angvel(b.angular_velocity)
                .linear_damping(b.linear_damping)
                .angular_damping(b.angular_damping)
                .can_sleep(false)
                .ccd_enabled(false);
            if b.fixed_rotation {
                builder = builder.lock_rotations();
            }
            let shape = Shape::from_def(&b.shape)
                .map_err(|e| anyhow::anyhow!("Rapier body {i}: bad polygon: {e}"))?;
            let collider = match (&b.shape, shape) {
                (TumbleShape::Box { half_extents }, _) => {
                    ColliderBuilder::cuboid(half_extents[0], half_extents[1])
                }
                (_, Shape::Circle(c)) => ColliderBuilder::ball(c.radius),
                (_, Shape::Polygon(p)) => {
                    let points: Vec<Vector> =
                        p.points().iter().map(|v| Vector::new(v.x, v.y)).collect();
                    ColliderBuilder::convex_polyline(points).with_context(|| {
                        format!("Rapier body {i}: the polygon is not convex for Rapier")
                    })?
                }
            };
            let collider = collider
                .density(b.density)
                .friction(b.friction)
                .friction_combine_rule(CoefficientCombineRule::GeometricMean)
                .restitution(b.restitution)
                .restitution_combine_rule(CoefficientCombineRule::Max);
            let (handle, _) = world.insert(builder, collider);
            handles.push(handle);
        }
        Ok(Rapier {
            world,
            handles,
            pool,
        })
    }
}

impl Peer for Rapier {
    fn step(&mut self) -> Result<()> {
        let world = &mut self.world;
        self.pool.install(|| world.step());
        Ok(())
    }

    fn pose(&mut self, index: usize) -> Result<[f32; 3]> {
        let body = &self.world.bodies[self.handles[index]];
        let p = body.translation();
        Ok([p.x, p.y, body.rotation().angle()])
    }

    fn velocity(&mut self, index: usize) -> Result<[f32; 3]> {
        let body = &self.world.bodies[self.handles[index]];
        let v = body.linvel();
        Ok([v.x, v.y, body.angvel()])
    }
}
