//! The deepest overlap between any two bodies, computed from poses alone, so that every engine
//! is measured by the same code: each pair whose bounding boxes overlap goes through tumble's
//! narrow phase (`collision::collide`, Box2D v3's manifold routines) at its pose, and the most
//! negative point separation is the penetration. The pair's transforms are taken relative to
//! body A's position in f64 first, so that a pile 10 km out is measured as precisely as one at
//! the origin.

use std::collections::HashMap;

use tumble_physics::collision::collide;
use tumble_physics::{BodyKind, Rot, SceneDef, Shape, Transform, Vec2};

/// The scene's shapes and kinds, built once per case.
pub struct Geometry {
    shapes: Vec<Shape>,
    kinds: Vec<BodyKind>,
    /// Largest centre-to-surface distance of any non-static body (the grid's cell size / 2).
    reach: f32,
}

impl Geometry {
    pub fn new(scene: &SceneDef) -> Geometry {
        let shapes: Vec<Shape> = scene
            .bodies
            .iter()
            .map(|b| {
                Shape::from_def(b.first_shape().expect("a body has a shape"))
                    .expect("a validated scene's shapes build")
            })
            .collect();
        let kinds: Vec<BodyKind> = scene.bodies.iter().map(|b| b.kind).collect();
        let reach = shapes
            .iter()
            .zip(&kinds)
            .filter(|(_, k)| **k != BodyKind::Static)
            .map(|(s, _)| s.extent())
            .fold(0.0_f32, f32::max);
        Geometry {
            shapes,
            kinds,
            reach,
        }
    }

    /// The deepest overlap (m, >= 0; 0 when nothing overlaps) at the poses `(x, y, angle)`,
    /// one per body in scene order.
    pub fn deepest_overlap(&self, poses: &[[f32; 3]]) -> f64 {
        let n = poses.len().min(self.shapes.len());
        let mut deepest = 0.0_f64;
        let aabb = |i: usize| {
            let xf = Transform {
                p: Vec2::new(poses[i][0], poses[i][1]),
                q: Rot::from_angle(poses[i][2]),
            };
            self.shapes[i].aabb(xf)
        };
        let statics: Vec<usize> = (0..n)
            .filter(|&i| self.kinds[i] == BodyKind::Static)
            .collect();
        let movers: Vec<usize> = (0..n)
            .filter(|&i| self.kinds[i] != BodyKind::Static)
            .collect();
        let static_boxes: Vec<_> = statics.iter().map(|&i| aabb(i)).collect();
        // Movers against statics (few statics in every case): box test, then the narrow phase.
        for &m in &movers {
            let b = aabb(m);
            for (k, &s) in statics.iter().enumerate() {
                if b.overlaps(&static_boxes[k]) {
                    deepest = deepest.max(self.pair_overlap(poses, s, m));
                }
            }
        }
        // Movers against movers: a uniform grid of cells twice the largest reach, each body in
        // the cell of its centre, so two touching bodies are in the same or neighbouring cells.
        let cell = f64::from(2.0 * self.reach.max(1e-3));
        let key = |i: usize| {
            (
                (f64::from(poses[i][0]) / cell).floor() as i64,
                (f64::from(poses[i][1]) / cell).floor() as i64,
            )
        };
        let mut grid: HashMap<(i64, i64), Vec<usize>> = HashMap::new();
        for &m in &movers {
            grid.entry(key(m)).or_default().push(m);
        }
        for &a in &movers {
            let (cx, cy) = key(a);
            let box_a = aabb(a);
            for dx in -1..=1 {
                for dy in -1..=1 {
                    let Some(list) = grid.get(&(cx + dx, cy + dy)) else {
                        continue;
                    };
                    for &b in list {
                        if b > a && box_a.overlaps(&aabb(b)) {
                            deepest = deepest.max(self.pair_overlap(poses, a, b));
                        }
                    }
                }
            }
        }
        deepest
    }

    /// The overlap (m, >= 0) of two bodies at their poses.
    fn pair_overlap(&self, poses: &[[f32; 3]], a: usize, b: usize) -> f64 {
        // The narrow phase wants the polygon first when a polygon meets a circle.
        let (a, b) = match (&self.shapes[a], &self.shapes[b]) {
            (Shape::Circle(_), Shape::Polygon(_)) => (b, a),
            _ => (a, b),
        };
        let rel = Vec2::new(
            (f64::from(poses[b][0]) - f64::from(poses[a][0])) as f32,
            (f64::from(poses[b][1]) - f64::from(poses[a][1])) as f32,
        );
        let xf_a = Transform {
            p: Vec2::ZERO,
            q: Rot::from_angle(poses[a][2]),
        };
        let xf_b = Transform {
            p: rel,
            q: Rot::from_angle(poses[b][2]),
        };
        let m = collide(&self.shapes[a], xf_a, &self.shapes[b], xf_b, 0.0);
        m.points()
            .iter()
            .map(|p| -f64::from(p.separation))
            .fold(0.0, f64::max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tumble_physics::{BodyDef, ShapeDef};

    fn unit_box() -> ShapeDef {
        ShapeDef::Box {
            half_extents: [0.5, 0.5],
            radius: 0.0,
        }
    }

    #[test]
    fn measures_box_and_circle_overlaps_anywhere() {
        for origin in [0.0_f32, 10_000.0] {
            let mut scene = SceneDef::new("t");
            scene.push(
                BodyDef::new(ShapeDef::Box {
                    half_extents: [10.0, 0.5],
                    radius: 0.0,
                })
                .kind(BodyKind::Static)
                .at(origin, origin - 0.5),
            );
            scene.push(BodyDef::new(unit_box()).at(origin, origin + 0.5));
            scene.push(BodyDef::new(unit_box()).at(origin, origin + 1.5));
            scene.push(BodyDef::new(ShapeDef::Circle { radius: 0.5 }).at(origin + 3.0, origin));
            let g = Geometry::new(&scene);
            let poses = |b1: f32, b2: f32, c: f32| {
                vec![
                    [origin, origin - 0.5, 0.0],
                    [origin, origin + 0.5 - b1, 0.0],
                    [origin, origin + 1.5 - b2, 0.0],
                    [origin + 3.0, origin + 0.5 - c, 0.0],
                ]
            };
            // Resting exactly: nothing overlaps.
            assert!(g.deepest_overlap(&poses(0.0, 0.0, 0.0)) < 1e-3);
            // The lower box 2 cm into the ground (the upper one follows it).
            let d = g.deepest_overlap(&poses(0.02, 0.02, 0.0));
            assert!((d - 0.02).abs() < 2e-3, "{origin}: {d}");
            // The upper box 5 cm into the lower one.
            let d = g.deepest_overlap(&poses(0.0, 0.05, 0.0));
            assert!((d - 0.05).abs() < 2e-3, "{origin}: {d}");
            // The circle 3 cm into the ground.
            let d = g.deepest_overlap(&poses(0.0, 0.0, 0.03));
            assert!((d - 0.03).abs() < 2e-3, "{origin}: {d}");
        }
    }
}
