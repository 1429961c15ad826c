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

/// rapier2d's crate version.
pub fn version() -> &'static str {
    rapier2d::VERSION
}

impl Rapier {
    /// Builds the scene.
    pub fn new(scene: &SceneDef, threads: usize) -> Result<Rapier> {
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
}
