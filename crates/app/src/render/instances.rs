//! What the GPU draws, laid out explicitly (bytemuck `Pod`, `#[repr(C)]`, no padding): one
//! instance per circle, one per polygon, two vertices per debug line; and the code that
//! fills them from the world.
//!
//! Vertex attributes are written out with `offset_of!`, not with `vertex_attr_array!`, whose
//! offsets assume tightly packed fields in declaration order and would silently go wrong if a
//! field were ever added with padding.

use std::mem::{offset_of, size_of};

use bytemuck::{Pod, Zeroable};
use glam::Vec2;
use tumble_physics::{BodyKind, MAX_POLYGON_VERTICES, Shape, World};
use wgpu::{VertexAttribute, VertexBufferLayout, VertexFormat, VertexStepMode};

use crate::camera::Camera;
use crate::settings::DebugDraw;

/// One circle: centre, rotation (cos, sin), colour, radius. 36 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct CircleInstance {
    /// World position of the centre (m).
    pub center: [f32; 2],
    /// Rotation as (cos, sin).
    pub rotation: [f32; 2],
    /// Fill colour, RGBA in 0..1 (gamma space).
    pub color: [f32; 4],
    /// Radius (m).
    pub radius: f32,
}

/// One convex polygon: centre, rotation, colour, up to eight vertices in the body's frame
/// (two per `[f32; 4]`), their bounding box in the body's frame, and the vertex count.
/// 116 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct PolygonInstance {
    /// World position of the body's origin (its centroid).
    pub center: [f32; 2],
    /// Rotation as (cos, sin).
    pub rotation: [f32; 2],
    /// Fill colour.
    pub color: [f32; 4],
    /// Vertices, two per entry: (v0, v1), (v2, v3), (v4, v5), (v6, v7).
    pub vertices: [[f32; 4]; 4],
    /// The vertices' bounding box in the body's frame: (min x, min y, max x, max y). The quad
    /// covers it (plus a margin for the soft edge), so a box's quad is the box itself and no
    /// fragment is shaded for nothing.
    pub bounds: [f32; 4],
    /// Vertices used, 3 to 8.
    pub count: u32,
}

/// One end of a debug line. 24 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct LineVertex {
    /// World position (m).
    pub position: [f32; 2],
    /// RGBA.
    pub color: [f32; 4],
}

const fn attr(format: VertexFormat, offset: usize, location: u32) -> VertexAttribute {
    VertexAttribute {
        format,
        offset: offset as u64,
        shader_location: location,
    }
}

impl CircleInstance {
    /// Attribute locations 0..=3, as `shapes.wgsl` reads them.
    pub const ATTRIBUTES: [VertexAttribute; 4] = [
        attr(VertexFormat::Float32x2, offset_of!(Self, center), 0),
        attr(VertexFormat::Float32x2, offset_of!(Self, rotation), 1),
        attr(VertexFormat::Float32x4, offset_of!(Self, color), 2),
        attr(VertexFormat::Float32, offset_of!(Self, radius), 3),
    ];

    /// The instance-rate buffer layout.
    pub fn layout() -> VertexBufferLayout<'static> {
        VertexBufferLayout {
            array_stride: size_of::<Self>() as u64,
            step_mode: VertexStepMode::Instance,
            attributes: &Self::ATTRIBUTES,
        }
    }
}

impl PolygonInstance {
    /// Attribute locations 0..=8, as `shapes.wgsl` reads them.
    pub const ATTRIBUTES: [VertexAttribute; 9] = [
        attr(VertexFormat::Float32x2, offset_of!(Self, center), 0),
        attr(VertexFormat::Float32x2, offset_of!(Self, rotation), 1),
        attr(VertexFormat::Float32x4, offset_of!(Self, color), 2),
        attr(VertexFormat::Float32x4, offset_of!(Self, vertices), 3),
        attr(VertexFormat::Float32x4, offset_of!(Self, vertices) + 16, 4),
        attr(VertexFormat::Float32x4, offset_of!(Self, vertices) + 32, 5),
        attr(VertexFormat::Float32x4, offset_of!(Self, vertices) + 48, 6),
        attr(VertexFormat::Float32x4, offset_of!(Self, bounds), 7),
        attr(VertexFormat::Uint32, offset_of!(Self, count), 8),
    ];

    /// The instance-rate buffer layout.
    pub fn layout() -> VertexBufferLayout<'static> {
        VertexBufferLayout {
            array_stride: size_of::<Self>() as u64,
            step_mode: VertexStepMode::Instance,
            attributes: &Self::ATTRIBUTES,
        }
    }
}

impl LineVertex {
    /// Attribute locations 0..=1, as `lines.wgsl` reads them.
    pub const ATTRIBUTES: [VertexAttribute; 2] = [
        attr(VertexFormat::Float32x2, offset_of!(Self, position), 0),
        attr(VertexFormat::Float32x4, offset_of!(Self, color), 1),
    ];

    /// The vertex-rate buffer layout.
    pub fn layout() -> VertexBufferLayout<'static> {
        VertexBufferLayout {
            array_stride: size_of::<Self>() as u64,
            step_mode: VertexStepMode::Vertex,
            attributes: &Self::ATTRIBUTES,
        }
    }
}

/// Fill colours by body kind (gamma-space RGB).
pub mod palette {
    /// The window's background.
    pub const BACKGROUND: [f32; 3] = [0.085, 0.095, 0.115];
    /// Static bodies: a calm slate.
    pub const STATIC: [f32; 3] = [0.42, 0.50, 0.52];
    /// Kinematic bodies: lavender.
    pub const KINEMATIC: [f32; 3] = [0.62, 0.52, 0.92];
    /// Grid lines every metre.
    pub const GRID: [f32; 4] = [1.0, 1.0, 1.0, 0.045];
    /// Grid lines every ten metres.
    pub const GRID_MAJOR: [f32; 4] = [1.0, 1.0, 1.0, 0.09];
}

/// HSV (all in 0..1, hue wrapping) to RGB.
pub fn hsv(h: f32, s: f32, v: f32) -> [f32; 3] {
    let h = h.rem_euclid(1.0) * 6.0;
    let c = v * s;
    let x = c * (1.0 - ((h % 2.0) - 1.0).abs());
    let (r, g, b) = match h as u32 {
        0 => (c, x, 0.0),
        1 => (x, c, 0.0),
        2 => (0.0, c, x),
        3 => (0.0, x, c),
        4 => (x, 0.0, c),
        _ => (c, 0.0, x),
    };
    let m = v - c;
    [r + m, g + m, b + m]
}

/// A dynamic body's colour by id: hues spread by the golden ratio, so neighbours differ.
pub fn dynamic_color(index: usize) -> [f32; 3] {
    let h = (index as f32 * 0.618_034).fract();
    hsv(0.08 + h * 0.6, 0.50, 0.95)
}

/// Colour from speed: blue at rest through green to red at 10 m/s and beyond.
pub fn speed_color(speed: f32) -> [f32; 3] {
    let t = (speed / 10.0).clamp(0.0, 1.0);
    hsv(0.62 - 0.62 * t, 0.6, 0.95)
}

/// The 24 constraint-graph colours (the last one, the overflow, is white).
pub fn graph_color(color: u8) -> [f32; 4] {
    if color >= 23 {
        return [1.0, 1.0, 1.0, 1.0];
    }
    let [r, g, b] = hsv(f32::from(color) * 0.618_034, 0.85, 1.0);
    [r, g, b, 1.0]
}

/// The CPU-side lists, refilled every frame (their capacity is kept).
#[derive(Debug, Default)]
pub struct Instances {
    /// Circles.
    pub circles: Vec<CircleInstance>,
    /// Polygons.
    pub polygons: Vec<PolygonInstance>,
    /// Debug lines, two vertices each.
    pub lines: Vec<LineVertex>,
}

fn with_dim(rgb: [f32; 3], dim: f32) -> [f32; 4] {
    let k = 1.0 - dim.clamp(0.0, 1.0);
    [rgb[0] * k, rgb[1] * k, rgb[2] * k, 1.0]
}

impl Instances {
    /// Empties the lists.
    pub fn clear(&mut self) {
        self.circles.clear();
        self.polygons.clear();
        self.lines.clear();
    }

    /// One instance per body. `dim` darkens everything (0: no change).
    pub fn add_bodies(&mut self, world: &World, color_by_speed: bool, dim: f32) {
        for i in 0..world.body_count() {
            let body = world.body(i);
            let rgb = match body.kind {
                BodyKind::Static => palette::STATIC,
                BodyKind::Kinematic => palette::KINEMATIC,
                BodyKind::Dynamic if color_by_speed => speed_color(body.linear_velocity.length()),
                BodyKind::Dynamic => dynamic_color(i),
            };
            let color = with_dim(rgb, dim);
            let center = body.position.to_array();
            let rotation = [body.rotation.c, body.rotation.s];
            match world.shape(i) {
                Shape::Circle(c) => self.circles.push(CircleInstance {
                    center,
                    rotation,
                    color,
                    radius: c.radius,
                }),
                Shape::Polygon(p) => {
                    let count = p.count.min(MAX_POLYGON_VERTICES);
                    let mut flat = [0.0f32; 16];
                    let (mut lo, mut hi) = (Vec2::splat(f32::MAX), Vec2::splat(f32::MIN));
                    for (k, v) in p.vertices[..count].iter().enumerate() {
                        flat[2 * k] = v.x;
                        flat[2 * k + 1] = v.y;
                        lo = lo.min(*v);
                        hi = hi.max(*v);
                    }
                    let vertices = std::array::from_fn(|j| {
                        [
                            flat[4 * j],
                            flat[4 * j + 1],
                            flat[4 * j + 2],
                            flat[4 * j + 3],
                        ]
                    });
                    self.polygons.push(PolygonInstance {
                        center,
                        rotation,
                        color,
                        vertices,
                        bounds: [lo.x, lo.y, hi.x, hi.y],
                        count: count as u32,
                    });
                }
            }
        }
    }

    /// A line from `a` to `b`.
    pub fn line(&mut self, a: Vec2, b: Vec2, color: [f32; 4]) {
        self.lines.push(LineVertex {
            position: a.to_array(),
            color,
        });
        self.lines.push(LineVertex {
            position: b.to_array(),
            color,
        });
    }

    /// The outline of an axis-aligned box.
    pub fn rect(&mut self, min: Vec2, max: Vec2, color: [f32; 4]) {
        let (a, b, c, d) = (min, Vec2::new(max.x, min.y), max, Vec2::new(min.x, max.y));
        self.line(a, b, color);
        self.line(b, c, color);
        self.line(c, d, color);
        self.line(d, a, color);
    }

    /// A small square marker of `half` metres around `p`.
    pub fn marker(&mut self, p: Vec2, half: f32, color: [f32; 4]) {
        self.rect(p - Vec2::splat(half), p + Vec2::splat(half), color);
    }

    /// A metre grid over the visible part of the world (every 10 m, 100 m, ... when zoomed
    /// out, so lines are never closer than about 24 pixels).
    pub fn add_grid(&mut self, camera: &Camera) {
        let mut spacing = 1.0f32;
        while spacing * camera.pixels_per_metre < 24.0 {
            spacing *= 10.0;
        }
        let view = camera.visible();
        let x0 = (view.min.x / spacing).floor() as i64;
        let x1 = (view.max.x / spacing).ceil() as i64;
        let y0 = (view.min.y / spacing).floor() as i64;
        let y1 = (view.max.y / spacing).ceil() as i64;
        if x1 - x0 > 400 || y1 - y0 > 400 {
            return;
        }
        for i in x0..=x1 {
            let x = i as f32 * spacing;
            let c = if i % 10 == 0 {
                palette::GRID_MAJOR
            } else {
                palette::GRID
            };
            self.line(Vec2::new(x, view.min.y), Vec2::new(x, view.max.y), c);
        }
        for j in y0..=y1 {
            let y = j as f32 * spacing;
            let c = if j % 10 == 0 {
                palette::GRID_MAJOR
            } else {
                palette::GRID
            };
            self.line(Vec2::new(view.min.x, y), Vec2::new(view.max.x, y), c);
        }
    }

    /// The debug overlays that `debug` turns on. Marker sizes are in pixels, so they read the
    /// same at every zoom.
    pub fn add_debug(&mut self, world: &World, debug: &DebugDraw, camera: &Camera) {
        let px = 1.0 / camera.pixels_per_metre;
        if debug.aabbs {
            for i in 0..world.body_count() {
                let b = world.fat_aabb(i);
                let c = match world.body(i).kind {
                    BodyKind::Static => [0.5, 0.7, 0.5, 0.6],
                    BodyKind::Kinematic => [0.7, 0.6, 1.0, 0.6],
                    BodyKind::Dynamic => [0.9, 0.4, 0.9, 0.6],
                };
                self.rect(b.min, b.max, c);
            }
        }
        if debug.tree {
            for node in world.broad_phase().nodes() {
                if !node.is_leaf() {
                    self.rect(node.aabb.min, node.aabb.max, [0.3, 0.8, 1.0, 0.35]);
                }
            }
        }
        if debug.contacts || debug.normals {
            for contact in world.contacts() {
                let m = contact.manifold;
                for point in m.points() {
                    if debug.contacts {
                        let c = if point.separation <= 0.0 {
                            [1.0, 0.25, 0.2, 1.0]
                        } else {
                            [1.0, 0.85, 0.2, 1.0]
                        };
                        self.marker(point.point, 2.5 * px, c);
                    }
                    if debug.normals {
                        self.line(
                            point.point,
                            point.point + m.normal * 18.0 * px,
                            [0.95, 0.95, 0.3, 0.9],
                        );
                    }
                }
            }
        }
        if debug.graph_colors {
            let colors = world.contact_colors();
            if !colors.is_empty() {
                let manifolds: Vec<_> = world.contacts().map(|c| c.manifold).collect();
                for (index, color) in colors {
                    let Some(m) = manifolds.get(index) else {
                        continue;
                    };
                    let c = graph_color(color);
                    for point in m.points() {
                        self.marker(point.point, 3.5 * px, c);
                        self.marker(point.point, 2.0 * px, c);
                    }
                }
            }
        }
        if debug.center_of_mass {
            let len = 10.0 * px;
            for i in 0..world.body_count() {
                let b = world.body(i);
                if b.kind == BodyKind::Static {
                    continue;
                }
                let x = b.rotation.apply(Vec2::X) * len;
                let y = b.rotation.apply(Vec2::Y) * len;
                self.line(b.position, b.position + x, [1.0, 0.3, 0.3, 1.0]);
                self.line(b.position, b.position + y, [0.3, 1.0, 0.3, 1.0]);
            }
        }
    }

    /// The held body's spring: a line from its anchor to the pointer.
    pub fn add_drag(&mut self, world: &World, drag: &crate::sim::Drag, camera: &Camera) {
        if drag.body >= world.body_count() {
            return;
        }
        let b = world.body(drag.body);
        let anchor = drag.anchor(b.position, b.rotation);
        let c = [1.0, 1.0, 1.0, 0.9];
        self.line(anchor, drag.target, c);
        self.marker(drag.target, 3.0 / camera.pixels_per_metre, c);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layouts_are_packed_as_the_shaders_read_them() {
        assert_eq!(size_of::<CircleInstance>(), 36);
        assert_eq!(size_of::<PolygonInstance>(), 116);
        assert_eq!(size_of::<LineVertex>(), 24);
        assert_eq!(offset_of!(PolygonInstance, vertices), 32);
        assert_eq!(offset_of!(PolygonInstance, count), 112);
        // Attributes never overlap and stay inside the stride.
        for attrs in [
            &CircleInstance::ATTRIBUTES[..],
            &PolygonInstance::ATTRIBUTES[..],
            &LineVertex::ATTRIBUTES[..],
        ] {
            let mut spans: Vec<(u64, u64)> = attrs
                .iter()
                .map(|a| (a.offset, a.offset + a.format.size()))
                .collect();
            spans.sort();
            for w in spans.windows(2) {
                assert!(w[0].1 <= w[1].0, "{spans:?}");
            }
        }
    }

    #[test]
    fn one_instance_per_body_by_shape_kind() {
        let scene = tumble_scene::builtin::build("falling_circles").unwrap();
        let world = crate::sim::build_world(&scene).unwrap();
        let mut inst = Instances::default();
        inst.add_bodies(&world, false, 0.0);
        assert_eq!(inst.circles.len() + inst.polygons.len(), world.body_count());
        assert!(!inst.circles.is_empty() && !inst.polygons.is_empty());
        for p in &inst.polygons {
            assert!((3..=8).contains(&p.count));
            assert!(p.bounds[0] < p.bounds[2] && p.bounds[1] < p.bounds[3]);
        }
    }
}
