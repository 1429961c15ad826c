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
use tumble_physics::{
    BodyId, BodyKind, DebugDraw, DrawOptions, MAX_POLYGON_VERTICES, ShapeDraw, Transform, World,
};
use wgpu::{VertexAttribute, VertexBufferLayout, VertexFormat, VertexStepMode};

use crate::camera::Camera;
use crate::settings::DebugLayers;

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

/// One convex polygon, maybe rounded, or a capsule (two vertices and a radius): centre,
/// rotation, colour, up to eight vertices in the shape's frame (two per `[f32; 4]`), their
/// bounding box in the shape's frame, the vertex count and the rounding radius. 120 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct PolygonInstance {
    /// World position of the shape's frame (its centroid).
    pub center: [f32; 2],
    /// Rotation as (cos, sin).
    pub rotation: [f32; 2],
    /// Fill colour.
    pub color: [f32; 4],
    /// Vertices, two per entry: (v0, v1), (v2, v3), (v4, v5), (v6, v7).
    pub vertices: [[f32; 4]; 4],
    /// The vertices' bounding box in the shape's frame: (min x, min y, max x, max y). The quad
    /// covers it (plus a margin for the soft edge), so a box's quad is the box itself and no
    /// fragment is shaded for nothing.
    pub bounds: [f32; 4],
    /// Vertices used: 3 to 8, or 2 for a capsule.
    pub count: u32,
    /// Rounding radius (m): the shape is every point this close to the polygon.
    pub radius: f32,
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
    /// Attribute locations 0..=9, as `shapes.wgsl` reads them.
    pub const ATTRIBUTES: [VertexAttribute; 10] = [
        attr(VertexFormat::Float32x2, offset_of!(Self, center), 0),
        attr(VertexFormat::Float32x2, offset_of!(Self, rotation), 1),
        attr(VertexFormat::Float32x4, offset_of!(Self, color), 2),
        attr(VertexFormat::Float32x4, offset_of!(Self, vertices), 3),
        attr(VertexFormat::Float32x4, offset_of!(Self, vertices) + 16, 4),
        attr(VertexFormat::Float32x4, offset_of!(Self, vertices) + 32, 5),
        attr(VertexFormat::Float32x4, offset_of!(Self, vertices) + 48, 6),
        attr(VertexFormat::Float32x4, offset_of!(Self, bounds), 7),
        attr(VertexFormat::Uint32, offset_of!(Self, count), 8),
        attr(VertexFormat::Float32, offset_of!(Self, radius), 9),
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

/// An island's colour: its slot hashed to a hue, so neighbouring islands differ.
pub fn island_color(island: usize) -> [f32; 3] {
    // A 32-bit integer hash (lowbias32), then the top bits as the hue.
    let mut x = island as u32;
    x ^= x >> 16;
    x = x.wrapping_mul(0x7feb_352d);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846c_a68b);
    x ^= x >> 16;
    hsv((x >> 8) as f32 / (1u32 << 24) as f32, 0.65, 0.95)
}

/// How much a sleeping body's colour is mixed toward the background.
pub const SLEEP_FADE: f32 = 0.5;

/// A sleeping body's colour: `rgb` mixed [`SLEEP_FADE`] of the way to the background.
pub fn asleep(rgb: [f32; 3]) -> [f32; 3] {
    std::array::from_fn(|k| rgb[k] + (palette::BACKGROUND[k] - rgb[k]) * SLEEP_FADE)
}

/// Colour from speed: blue at rest through green to red at 10 m/s and beyond.
pub fn speed_color(speed: f32) -> [f32; 3] {
    let t = (speed / 10.0).clamp(0.0, 1.0);
    hsv(0.62 - 0.62 * t, 0.6, 0.95)
}

/// How dynamic bodies are coloured.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Coloring {
    /// By body slot ([`dynamic_color`]).
    #[default]
    Id,
    /// By speed ([`speed_color`]).
    Speed,
    /// By island ([`island_color`]); a body without one by slot.
    Island,
}

impl Coloring {
    /// The colouring the debug-draw settings ask for (islands before speed).
    pub fn of(debug: &DebugLayers) -> Coloring {
        if debug.islands {
            Coloring::Island
        } else if debug.color_by_speed {
            Coloring::Speed
        } else {
            Coloring::Id
        }
    }
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

/// A polygon or capsule instance: the vertices packed two per `[f32; 4]`, the quad their
/// bounding box grown by the radius.
fn polygon_instance(
    center: [f32; 2],
    rotation: [f32; 2],
    color: [f32; 4],
    points: &[Vec2],
    radius: f32,
) -> PolygonInstance {
    let count = points.len().min(MAX_POLYGON_VERTICES);
    let mut flat = [0.0f32; 16];
    let (mut lo, mut hi) = (Vec2::splat(f32::MAX), Vec2::splat(f32::MIN));
    for (k, v) in points[..count].iter().enumerate() {
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
    let (lo, hi) = (lo - Vec2::splat(radius), hi + Vec2::splat(radius));
    PolygonInstance {
        center,
        rotation,
        color,
        vertices,
        bounds: [lo.x, lo.y, hi.x, hi.y],
        count: count as u32,
        radius,
    }
}

fn with_dim(rgb: [f32; 3], dim: f32) -> [f32; 4] {
    let k = 1.0 - dim.clamp(0.0, 1.0);
    [rgb[0] * k, rgb[1] * k, rgb[2] * k, 1.0]
}

/// The viewer's side of the library's debug drawing: solid shapes become circle and polygon
/// instances coloured as the viewer colours bodies ([`Coloring`], dimming, see-through
/// sensors), segment shapes and everything else become lines.
struct Painter<'a> {
    instances: &'a mut Instances,
    world: &'a World,
    coloring: Coloring,
    dim: f32,
    /// A body's shapes are mostly neighbours: its colour is worked out once per run.
    last: Option<(BodyId, [f32; 4])>,
}

impl<'a> Painter<'a> {
    fn new(instances: &'a mut Instances, world: &'a World, coloring: Coloring, dim: f32) -> Self {
        Self {
            instances,
            world,
            coloring,
            dim,
            last: None,
        }
    }

    fn fill(&mut self, shape: &ShapeDraw) -> [f32; 4] {
        let color = match self.last {
            Some((body, color)) if body == shape.body => color,
            _ => {
                let rgb = Instances::body_color(self.world, shape.body, self.coloring);
                let color = with_dim(rgb, self.dim);
                self.last = Some((shape.body, color));
                color
            }
        };
        // A sensor pushes nothing: drawn see-through, over what it detects.
        if shape.sensor {
            [color[0], color[1], color[2], color[3] * 0.3]
        } else {
            color
        }
    }
}

impl DebugDraw for Painter<'_> {
    fn draw_segment(&mut self, p1: Vec2, p2: Vec2, color: [f32; 4]) {
        self.instances.line(p1, p2, color);
    }

    fn draw_polygon(
        &mut self,
        transform: Transform,
        vertices: &[Vec2],
        radius: f32,
        _color: [f32; 4],
        shape: &ShapeDraw,
    ) {
        let color = self.fill(shape);
        let rotation = [transform.q.c, transform.q.s];
        self.instances.polygons.push(polygon_instance(
            transform.p.to_array(),
            rotation,
            color,
            vertices,
            radius,
        ));
    }

    fn draw_circle(
        &mut self,
        transform: Transform,
        radius: f32,
        _color: [f32; 4],
        shape: &ShapeDraw,
    ) {
        let color = self.fill(shape);
        self.instances.circles.push(CircleInstance {
            center: transform.p.to_array(),
            rotation: [transform.q.c, transform.q.s],
            color,
            radius,
        });
    }

    fn draw_capsule(
        &mut self,
        transform: Transform,
        center1: Vec2,
        center2: Vec2,
        radius: f32,
        color: [f32; 4],
        shape: &ShapeDraw,
    ) {
        // A capsule is the polygon of its two centres, rounded: the same instance.
        self.draw_polygon(transform, &[center1, center2], radius, color, shape);
    }

    fn draw_segment_shape(&mut self, p1: Vec2, p2: Vec2, _color: [f32; 4], shape: &ShapeDraw) {
        let color = self.fill(shape);
        self.instances.line(p1, p2, color);
    }

    fn draw_point(&mut self, p: Vec2, size: f32, color: [f32; 4]) {
        self.instances.marker(p, 0.5 * size, color);
    }
}

impl Instances {
    /// Empties the lists.
    pub fn clear(&mut self) {
        self.circles.clear();
        self.polygons.clear();
        self.lines.clear();
    }

    /// A body's fill colour (before dimming): by kind, dynamic ones by `coloring`, and a
    /// sleeping one faded toward the background ([`asleep`]).
    pub fn body_color(world: &World, id: BodyId, coloring: Coloring) -> [f32; 3] {
        let Ok(body) = world.body(id) else {
            return palette::STATIC;
        };
        let index = id.index as usize;
        let rgb = match body.kind {
            BodyKind::Static => palette::STATIC,
            BodyKind::Kinematic => palette::KINEMATIC,
            BodyKind::Dynamic => match coloring {
                Coloring::Speed => speed_color(body.linear_velocity.length()),
                Coloring::Island => world
                    .island_of(id)
                    .ok()
                    .flatten()
                    .map_or_else(|| dynamic_color(index), island_color),
                Coloring::Id => dynamic_color(index),
            },
        };
        if body.kind == BodyKind::Dynamic && !body.awake {
            asleep(rgb)
        } else {
            rgb
        }
    }

    /// One instance per shape of every live body, at the shape's own pose, in shape order
    /// (the order [`World::body_at`] picks from, so the body on top is the one grabbed),
    /// drawn through the library's [`World::draw`]. `dim` darkens everything (0: no change).
    pub fn add_bodies(&mut self, world: &World, coloring: Coloring, dim: f32) {
        let options = DrawOptions {
            shapes: true,
            ..DrawOptions::nothing()
        };
        world.draw(&mut Painter::new(self, world, coloring, dim), &options);
    }

    /// A white cross on each bullet's centre, so that the bodies swept against moving ones
    /// too stand out.
    pub fn add_bullets(&mut self, world: &World, camera: &Camera) {
        let half = 5.0 / camera.pixels_per_metre;
        for (_, body) in world.bodies() {
            if body.bullet {
                let p = body.position;
                let c = [1.0, 1.0, 1.0, 0.95];
                self.line(p - Vec2::new(half, half), p + Vec2::new(half, half), c);
                self.line(p - Vec2::new(half, -half), p + Vec2::new(half, -half), c);
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

    /// The debug overlays that `debug` turns on, drawn through the library's
    /// [`World::draw`]. Marker sizes are in pixels, so they read the same at every zoom.
    pub fn add_debug(&mut self, world: &World, debug: &DebugLayers, camera: &Camera) {
        let options = DrawOptions {
            aabbs: debug.aabbs,
            tree: debug.tree,
            mass: debug.center_of_mass,
            contacts: debug.contacts,
            contact_normals: debug.normals,
            chain_normals: debug.normals,
            graph_colors: debug.graph_colors,
            pixel: 1.0 / camera.pixels_per_metre,
            ..DrawOptions::nothing()
        };
        world.draw(&mut Painter::new(self, world, Coloring::Id, 0.0), &options);
    }

    /// What a played sample draws beside the world (the platformer's pogo and the planes
    /// holding its character), through the same painter.
    pub fn add_sample(&mut self, world: &World, controller: &tumble_scene::sample::Controller) {
        controller.draw(&mut Painter::new(self, world, Coloring::Id, 0.0));
    }

    /// Every joint, as the library's [`World::draw`] draws them (Box2D's way: body A's
    /// centre to its anchor, anchor to anchor, body B's anchor to its centre; a distance
    /// joint its anchors only; a slider's axis and limits, a hinge's limits as spokes; the
    /// mouse joint its target). With `forces`, each joint's reaction force on B as a line
    /// from B's anchor (a pixel per newton, at most 100 px).
    pub fn add_joints(&mut self, world: &World, forces: bool, camera: &Camera) {
        let options = DrawOptions {
            joints: true,
            joint_extras: true,
            joint_forces: forces,
            pixel: 1.0 / camera.pixels_per_metre,
            ..DrawOptions::nothing()
        };
        world.draw(&mut Painter::new(self, world, Coloring::Id, 0.0), &options);
    }

    /// The ray tool's ray from `from` to `to`, each shape it passes marked where it enters,
    /// with its normal there (30 px), the nearest hit in another colour.
    pub fn add_ray(&mut self, world: &World, from: Vec2, to: Vec2, camera: &Camera) {
        let ray = [1.0, 0.9, 0.3, 0.9];
        self.line(from, to, ray);
        let px = 1.0 / camera.pixels_per_metre;
        self.marker(from, 3.0 * px, ray);
        let hits = world.cast_ray_all(from, to - from, &tumble_physics::QueryFilter::default());
        for (k, hit) in hits.iter().enumerate() {
            let c = if k == 0 {
                [1.0, 0.35, 0.35, 1.0]
            } else {
                [1.0, 0.75, 0.4, 0.9]
            };
            self.marker(hit.point, 4.0 * px, c);
            self.line(hit.point, hit.point + hit.normal * (30.0 * px), c);
        }
    }

    /// The held body's spring: a line from its anchor to the pointer.
    pub fn add_drag(&mut self, world: &World, drag: &crate::sim::Drag, camera: &Camera) {
        let Ok(b) = world.body(drag.body) else {
            return;
        };
        let anchor = drag.anchor(b.position, b.rotation);
        let c = [1.0, 1.0, 1.0, 0.9];
        self.line(anchor, drag.target, c);
        self.marker(drag.target, 3.0 / camera.pixels_per_metre, c);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tumble_physics::Shape;

    #[test]
    fn layouts_are_packed_as_the_shaders_read_them() {
        assert_eq!(size_of::<CircleInstance>(), 36);
        assert_eq!(size_of::<PolygonInstance>(), 120);
        assert_eq!(offset_of!(PolygonInstance, radius), 116);
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

    /// One dynamic body of two parts, a box and a disc on either side of its origin, turned.
    fn compound_world() -> World {
        let mut scene = tumble_physics::SceneDef::new("compound");
        let parts = vec![
            tumble_physics::PartDef::new(tumble_physics::ShapeDef::Box {
                half_extents: [0.5, 0.25],
                radius: 0.0,
            })
            .at(1.0, 0.0, 0.3),
            tumble_physics::PartDef::new(tumble_physics::ShapeDef::Circle { radius: 0.4 })
                .at(-1.5, 0.5, 0.0),
        ];
        scene.push(
            tumble_physics::BodyDef::compound(parts)
                .at(3.0, 2.0)
                .angle(0.7),
        );
        crate::sim::build_world(&scene).unwrap()
    }

    #[test]
    fn sensors_are_see_through_bullets_are_crossed_and_a_ray_marks_its_hits() {
        // A body with a solid box and a sensor disc, a bullet ball, and a static wall.
        let mut scene = tumble_physics::SceneDef::new("marks");
        scene.push(tumble_physics::BodyDef::compound(vec![
            tumble_physics::PartDef::new(tumble_physics::ShapeDef::Box {
                half_extents: [0.5, 0.5],
                radius: 0.0,
            }),
            tumble_physics::PartDef::new(tumble_physics::ShapeDef::Circle { radius: 2.0 })
                .sensor(true),
        ]));
        scene.push(
            tumble_physics::BodyDef::new(tumble_physics::ShapeDef::Circle { radius: 0.2 })
                .at(5.0, 0.0)
                .bullet(true),
        );
        scene.push(
            tumble_physics::BodyDef::new(tumble_physics::ShapeDef::Box {
                half_extents: [0.25, 3.0],
                radius: 0.0,
            })
            .kind(BodyKind::Static)
            .at(10.0, 0.0),
        );
        let world = crate::sim::build_world(&scene).unwrap();
        let mut inst = Instances::default();
        inst.add_bodies(&world, Coloring::Id, 0.0);
        let sensor = inst.circles.iter().find(|c| c.radius == 2.0).unwrap();
        let solid = &inst.polygons[0];
        assert_eq!(solid.color[3], 1.0);
        assert!((sensor.color[3] - 0.3).abs() < 1e-6, "{:?}", sensor.color);
        // One cross (two lines, four vertices) on the one bullet.
        let camera = Camera::new(Vec2::ZERO, 20.0, Vec2::new(800.0, 600.0));
        let before = inst.lines.len();
        inst.add_bullets(&world, &camera);
        assert_eq!(inst.lines.len() - before, 4);
        // A ray along y = 0.1 from the left: the box, the ball and the wall (the sensor is
        // not hit), each marked and given its normal, after the ray and its start marker.
        let before = inst.lines.len();
        inst.add_ray(&world, Vec2::new(-5.0, 0.1), Vec2::new(15.0, 0.1), &camera);
        let marker = {
            let mut m = Instances::default();
            m.marker(Vec2::ZERO, 1.0, [1.0; 4]);
            m.lines.len()
        };
        assert_eq!(inst.lines.len() - before, 2 + marker + 3 * (marker + 2));
    }

    #[test]
    fn every_shape_of_a_compound_body_is_drawn_at_its_own_pose() {
        let world = compound_world();
        assert_eq!(world.body_count(), 1);
        let mut inst = Instances::default();
        inst.add_bodies(&world, Coloring::Id, 0.0);
        assert_eq!((inst.circles.len(), inst.polygons.len()), (1, 1));
        let shapes: Vec<_> = world.body_shapes(BodyId::scene(0)).unwrap().collect();
        assert_eq!(shapes.len(), 2);
        let body = world.body(BodyId::scene(0)).unwrap();
        for view in shapes {
            let (center, rotation) = match view.shape {
                Shape::Circle(_) => (inst.circles[0].center, inst.circles[0].rotation),
                Shape::Polygon(_) => (inst.polygons[0].center, inst.polygons[0].rotation),
                other => panic!("the scene has no {other:?}"),
            };
            assert_eq!(center, view.transform.p.to_array());
            assert_eq!(rotation, [view.transform.q.c, view.transform.q.s]);
            // Not at the body's pose: each part is off the centre of mass.
            assert!((view.transform.p - body.position).length() > 0.5);
        }
        // The box part is turned 0.3 rad more than its body.
        let q = inst.polygons[0].rotation;
        assert!((q[1].atan2(q[0]) - 1.0).abs() < 1e-5, "{q:?}");
        // Both parts have the body's colour.
        assert_eq!(inst.circles[0].color, inst.polygons[0].color);
    }

    #[test]
    fn removed_bodies_are_not_drawn() {
        let scene = tumble_scene::builtin::build("falling_circles").unwrap();
        let mut world = crate::sim::build_world(&scene).unwrap();
        let n = world.body_count();
        let circle = world
            .shapes()
            .filter(|v| matches!(v.shape, Shape::Circle(_)))
            .last()
            .unwrap()
            .body;
        let at = world.body(circle).unwrap().position;
        world.destroy_body(circle).unwrap();
        let mut inst = Instances::default();
        inst.add_bodies(&world, Coloring::Id, 0.0);
        assert_eq!(inst.circles.len() + inst.polygons.len(), n - 1);
        assert!(inst.circles.iter().all(|c| c.center != at.to_array()));
        let mut debug = crate::settings::Settings::default().debug;
        debug.aabbs = true;
        debug.center_of_mass = true;
        let camera = Camera::new(Vec2::ZERO, 20.0, Vec2::new(800.0, 600.0));
        inst.add_debug(&world, &debug, &camera);
        // A box (4 lines, 8 vertices) per live shape, axes (2 lines) per moving body.
        let moving = world
            .bodies()
            .filter(|(_, b)| b.kind != BodyKind::Static)
            .count();
        assert_eq!(inst.lines.len(), 8 * (n - 1) + 4 * moving);
    }

    /// Lines only, as an application that writes nothing but `draw_segment` gets them.
    struct LineCount(usize);

    impl DebugDraw for LineCount {
        fn draw_segment(&mut self, _: Vec2, _: Vec2, _: [f32; 4]) {
            self.0 += 1;
        }
    }

    #[test]
    fn the_debug_layer_and_joints_are_the_library_s_drawing() {
        // Ragdolls: hinges with limits and contacts, stepped until things touch.
        let scene = tumble_scene::builtin::build("ragdoll").unwrap();
        let mut world = crate::sim::build_world(&scene).unwrap();
        for _ in 0..120 {
            world.step(scene.dt, scene.substeps);
        }
        let joints = world.joint_ids().count();
        assert!(
            joints > 0 && world.contact_count() > 0,
            "{joints} joints, {} contacts",
            world.contact_count()
        );
        let mut debug = crate::settings::Settings::default().debug;
        (debug.aabbs, debug.tree, debug.contacts, debug.normals) = (true, true, true, true);
        (debug.graph_colors, debug.center_of_mass) = (true, true);
        let camera = Camera::new(Vec2::ZERO, 20.0, Vec2::new(800.0, 600.0));
        let mut inst = Instances::default();
        inst.add_debug(&world, &debug, &camera);
        inst.add_joints(&world, true, &camera);
        // Every line the library draws is one line of the viewer (two vertices), points
        // included (a square of four), and nothing else is added.
        let mut lines = LineCount(0);
        let px = 1.0 / camera.pixels_per_metre;
        let options = tumble_physics::DrawOptions {
            aabbs: true,
            tree: true,
            mass: true,
            contacts: true,
            contact_normals: true,
            chain_normals: true,
            graph_colors: true,
            joints: true,
            joint_extras: true,
            joint_forces: true,
            shapes: false,
            bounds: None,
            pixel: px,
        };
        world.draw(&mut lines, &options);
        assert!(lines.0 > 0);
        assert_eq!(inst.lines.len(), 2 * lines.0);
    }

    fn sleep_scene(awake: bool) -> World {
        let mut scene = tumble_physics::SceneDef::new("sleepy");
        scene.sleep = true;
        scene.push(
            tumble_physics::BodyDef::new(tumble_physics::ShapeDef::Circle { radius: 0.5 })
                .at(0.0, 3.0)
                .awake(awake),
        );
        crate::sim::build_world(&scene).unwrap()
    }

    #[test]
    fn a_sleeping_body_is_drawn_faded() {
        let (awake, asleep_world) = (sleep_scene(true), sleep_scene(false));
        assert!(awake.is_awake(BodyId::scene(0)).unwrap());
        assert!(!asleep_world.is_awake(BodyId::scene(0)).unwrap());
        let color = |world: &World| {
            let mut inst = Instances::default();
            inst.add_bodies(world, Coloring::Id, 0.0);
            inst.circles[0].color
        };
        let (lit, faded) = (color(&awake), color(&asleep_world));
        assert_ne!(lit, faded);
        assert_eq!(lit, with_dim(dynamic_color(0), 0.0));
        assert_eq!(faded, with_dim(asleep(dynamic_color(0)), 0.0));
        // Halfway to the background.
        for k in 0..3 {
            let mid = (lit[k] + palette::BACKGROUND[k]) / 2.0;
            assert!((faded[k] - mid).abs() < 1e-6, "{faded:?}");
        }
        // Static bodies never count as awake, and are not faded.
        let mut statics = tumble_physics::SceneDef::new("ground");
        statics.push(
            tumble_physics::BodyDef::new(tumble_physics::ShapeDef::Circle { radius: 1.0 })
                .kind(BodyKind::Static),
        );
        let ground = crate::sim::build_world(&statics).unwrap();
        assert_eq!(color(&ground), with_dim(palette::STATIC, 0.0));
    }

    #[test]
    fn islands_colour_dynamic_bodies_by_island() {
        let mut scene = tumble_physics::SceneDef::new("apart");
        for x in [-5.0, 5.0] {
            scene.push(
                tumble_physics::BodyDef::new(tumble_physics::ShapeDef::Circle { radius: 0.5 })
                    .at(x, 0.0),
            );
        }
        scene.gravity = [0.0, 0.0];
        let mut world = crate::sim::build_world(&scene).unwrap();
        world.step(scene.dt, scene.substeps);
        let (a, b) = (
            world.island_of(BodyId::scene(0)).unwrap(),
            world.island_of(BodyId::scene(1)).unwrap(),
        );
        let (Some(a), Some(b)) = (a, b) else {
            panic!("dynamic bodies without islands: {a:?} {b:?}");
        };
        assert_ne!(a, b);
        let mut inst = Instances::default();
        inst.add_bodies(&world, Coloring::Island, 0.0);
        assert_eq!(inst.circles[0].color, with_dim(island_color(a), 0.0));
        assert_eq!(inst.circles[1].color, with_dim(island_color(b), 0.0));
        assert_ne!(inst.circles[0].color, inst.circles[1].color);
        let debug = DebugLayers {
            islands: true,
            color_by_speed: true,
            ..DebugLayers::default()
        };
        assert_eq!(Coloring::of(&debug), Coloring::Island);
    }

    #[test]
    fn one_instance_per_body_by_shape_kind() {
        let scene = tumble_scene::builtin::build("falling_circles").unwrap();
        let world = crate::sim::build_world(&scene).unwrap();
        let mut inst = Instances::default();
        inst.add_bodies(&world, Coloring::Id, 0.0);
        assert_eq!(inst.circles.len() + inst.polygons.len(), world.body_count());
        assert!(!inst.circles.is_empty() && !inst.polygons.is_empty());
        for p in &inst.polygons {
            assert!((3..=8).contains(&p.count));
            assert!(p.bounds[0] < p.bounds[2] && p.bounds[1] < p.bounds[3]);
        }
    }
}
