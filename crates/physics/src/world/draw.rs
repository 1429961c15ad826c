//! Debug drawing: the world told shape by shape, joint by joint and contact by contact to a
//! [`DebugDraw`] the application implements, as Box2D v3's `b2World_Draw` tells its
//! `b2DebugDraw`. The library knows no renderer: an application that implements only
//! [`DebugDraw::draw_segment`] sees every outline, joint and (with [`DrawOptions`]) contact,
//! and one that draws filled shapes overrides the solid methods and picks its own colours
//! from the [`ShapeDraw`] each carries.

use glam::Vec2;

use crate::def::BodyKind;
use crate::id::{BodyId, JointId, ShapeId};
use crate::joint::JointKind;
use crate::math::{Rot, Transform};
use crate::shape::{Aabb, Shape};

use super::World;

/// A colour: red, green, blue and opacity, each 0 to 1.
pub type Color = [f32; 4];

/// The colours [`World::draw`] picks (Box2D's `b2HexColor` choices in `b2World_Draw`, as
/// linear RGBA), for applications that want to match them.
pub mod colors {
    use super::Color;

    /// A static body's shapes (Box2D: pale green).
    pub const STATIC: Color = [0.596, 0.984, 0.596, 1.0];
    /// A kinematic body's shapes (royal blue).
    pub const KINEMATIC: Color = [0.255, 0.412, 0.882, 1.0];
    /// An awake dynamic body's shapes (pink).
    pub const AWAKE: Color = [1.0, 0.753, 0.796, 1.0];
    /// A sleeping dynamic body's shapes (grey).
    pub const ASLEEP: Color = [0.5, 0.5, 0.5, 1.0];
    /// A bullet's shapes (turquoise).
    pub const BULLET: Color = [0.251, 0.878, 0.816, 1.0];
    /// A sensor, see-through (wheat).
    pub const SENSOR: Color = [0.961, 0.871, 0.702, 0.5];
    /// Joints: the lines between centres and anchors.
    pub const JOINT: Color = [0.55, 0.85, 0.85, 0.9];
    /// A joint's limits.
    pub const LIMIT: Color = [1.0, 0.8, 0.3, 0.9];
    /// A slider's axis.
    pub const AXIS: Color = [0.5, 0.6, 0.9, 0.8];
    /// A joint's reaction force on body B.
    pub const FORCE: Color = [1.0, 0.6, 0.2, 1.0];
    /// A contact point that touches (separation at most 0).
    pub const TOUCHING: Color = [1.0, 0.25, 0.2, 1.0];
    /// A speculative contact point (not yet touching).
    pub const SPECULATIVE: Color = [1.0, 0.85, 0.2, 1.0];
    /// A contact normal.
    pub const NORMAL: Color = [0.95, 0.95, 0.3, 0.9];
    /// A chain segment's pushing side.
    pub const CHAIN_SIDE: Color = [0.4, 0.9, 1.0, 0.9];
    /// A static body's shapes' fat boxes.
    pub const AABB_STATIC: Color = [0.5, 0.7, 0.5, 0.6];
    /// A kinematic body's shapes' fat boxes.
    pub const AABB_KINEMATIC: Color = [0.7, 0.6, 1.0, 0.6];
    /// A dynamic body's shapes' fat boxes.
    pub const AABB_DYNAMIC: Color = [0.9, 0.4, 0.9, 0.6];
    /// The broad phase's inner nodes.
    pub const TREE: Color = [0.3, 0.8, 1.0, 0.35];
}

/// The colour of constraint-graph colour `color` (23, the overflow, is white): hues spread by
/// the golden ratio so neighbouring colours differ.
pub fn graph_color(color: u8) -> Color {
    if color >= 23 {
        return [1.0, 1.0, 1.0, 1.0];
    }
    let h = (f32::from(color) * 0.618_034).fract() * 6.0;
    let (s, v) = (0.85f32, 1.0f32);
    let c = v * s;
    let x = c * (1.0 - ((h % 2.0) - 1.0).abs());
    let [r, g, b] = match h as u32 {
        0 => [c, x, 0.0],
        1 => [x, c, 0.0],
        2 => [0.0, c, x],
        3 => [0.0, x, c],
        4 => [x, 0.0, c],
        _ => [c, 0.0, x],
    };
    let m = v - c;
    [r + m, g + m, b + m, 1.0]
}

/// What a solid shape being drawn is, so that an application can choose its own colour (by
/// body, by speed, by island) instead of the one passed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ShapeDraw {
    /// The shape.
    pub shape: ShapeId,
    /// Its body.
    pub body: BodyId,
    /// The body's kind.
    pub kind: BodyKind,
    /// Whether the body is awake (static bodies count as awake).
    pub awake: bool,
    /// Whether the shape is a sensor.
    pub sensor: bool,
    /// Whether the body is a bullet.
    pub bullet: bool,
}

/// Sides of the polygon a circle's default outline is drawn as.
const CIRCLE_SIDES: usize = 24;
/// Segments of each rounded corner of a polygon's or capsule's default outline.
const ARC_STEPS: usize = 6;

/// Where [`World::draw`] sends what it draws. Only [`DebugDraw::draw_segment`] must be
/// written: every other method's default draws an outline through it, so a renderer of lines
/// sees everything. A method's points are in world coordinates (metres) unless it says
/// otherwise.
pub trait DebugDraw {
    /// A line segment from `p1` to `p2`.
    fn draw_segment(&mut self, p1: Vec2, p2: Vec2, color: Color);

    /// A convex polygon, `vertices` counter-clockwise in the frame `transform`, rounded by
    /// `radius` (0: sharp corners). By default its outline: each edge pushed out by `radius`,
    /// joined by arcs at the corners.
    fn draw_polygon(
        &mut self,
        transform: Transform,
        vertices: &[Vec2],
        radius: f32,
        color: Color,
        shape: &ShapeDraw,
    ) {
        let _ = shape;
        rounded_outline(self, transform, vertices, radius, color);
    }

    /// A circle of `radius` centred on `transform.p`. By default a polygon of 24 sides and a
    /// radius line along the frame's x axis, so that turning shows.
    fn draw_circle(&mut self, transform: Transform, radius: f32, color: Color, shape: &ShapeDraw) {
        let _ = shape;
        let at = |k: usize| {
            let a = k as f32 * std::f32::consts::TAU / CIRCLE_SIDES as f32;
            transform.p + Vec2::new(a.cos(), a.sin()) * radius
        };
        for k in 0..CIRCLE_SIDES {
            self.draw_segment(at(k), at(k + 1), color);
        }
        self.draw_segment(
            transform.p,
            transform.p + transform.q.apply(Vec2::X) * radius,
            color,
        );
    }

    /// A capsule: the points within `radius` of the segment from `center1` to `center2`,
    /// both in the frame `transform`. By default its outline.
    fn draw_capsule(
        &mut self,
        transform: Transform,
        center1: Vec2,
        center2: Vec2,
        radius: f32,
        color: Color,
        shape: &ShapeDraw,
    ) {
        let _ = shape;
        rounded_outline(self, transform, &[center1, center2], radius, color);
    }

    /// A segment or chain-segment shape from `p1` to `p2`. By default a segment.
    fn draw_segment_shape(&mut self, p1: Vec2, p2: Vec2, color: Color, shape: &ShapeDraw) {
        let _ = shape;
        self.draw_segment(p1, p2, color);
    }

    /// A point drawn `size` metres across. By default a square outline.
    fn draw_point(&mut self, p: Vec2, size: f32, color: Color) {
        let h = 0.5 * size;
        let corners = [
            p + Vec2::new(-h, -h),
            p + Vec2::new(h, -h),
            p + Vec2::new(h, h),
            p + Vec2::new(-h, h),
        ];
        for k in 0..4 {
            self.draw_segment(corners[k], corners[(k + 1) % 4], color);
        }
    }

    /// A frame: its x axis in red, its y axis in green, each `length` metres long.
    fn draw_transform(&mut self, transform: Transform, length: f32) {
        let p = transform.p;
        self.draw_segment(
            p,
            p + transform.q.apply(Vec2::X) * length,
            [1.0, 0.3, 0.3, 1.0],
        );
        self.draw_segment(
            p,
            p + transform.q.apply(Vec2::Y) * length,
            [0.3, 1.0, 0.3, 1.0],
        );
    }

    /// An axis-aligned box. By default its four sides.
    fn draw_aabb(&mut self, aabb: Aabb, color: Color) {
        let (a, c) = (aabb.min, aabb.max);
        let (b, d) = (Vec2::new(c.x, a.y), Vec2::new(a.x, c.y));
        self.draw_segment(a, b, color);
        self.draw_segment(b, c, color);
        self.draw_segment(c, d, color);
        self.draw_segment(d, a, color);
    }
}

/// The outline of the points within `radius` of the convex polygon `core` (2 points: a
/// capsule's segment), in the frame `transform`: each edge pushed out along its normal, the
/// corners joined by arcs.
fn rounded_outline<D: DebugDraw + ?Sized>(
    draw: &mut D,
    transform: Transform,
    core: &[Vec2],
    radius: f32,
    color: Color,
) {
    let n = core.len();
    if n == 0 {
        return;
    }
    let world = |p: Vec2| transform.apply(p);
    if radius <= 0.0 {
        for k in 0..n {
            draw.draw_segment(world(core[k]), world(core[(k + 1) % n]), color);
        }
        return;
    }
    // The outward normal of edge k (from core[k] to core[k+1]); a capsule's two "edges" are
    // the segment both ways, so its normals are opposite.
    let normal = |k: usize| {
        let e = core[(k + 1) % n] - core[k];
        Vec2::new(e.y, -e.x).normalize_or_zero()
    };
    for k in 0..n {
        let (a, b, nk) = (core[k], core[(k + 1) % n], normal(k));
        draw.draw_segment(world(a + nk * radius), world(b + nk * radius), color);
        // The arc round core[k+1], from this edge's normal to the next one's, counter-clockwise.
        let next = normal((k + 1) % n);
        let start = nk.y.atan2(nk.x);
        let mut sweep = next.y.atan2(next.x) - start;
        if sweep < 0.0 {
            sweep += std::f32::consts::TAU;
        }
        let mut last = b + nk * radius;
        for step in 1..=ARC_STEPS {
            let t = start + sweep * step as f32 / ARC_STEPS as f32;
            let p = b + Vec2::new(t.cos(), t.sin()) * radius;
            draw.draw_segment(world(last), world(p), color);
            last = p;
        }
    }
}

/// What [`World::draw`] draws, and at what scale. [`Default`] draws the shapes and joints
/// only, for a view of 50 pixels a metre.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DrawOptions {
    /// Every shape, in shape order (so that the last drawn is the one [`World::body_at`]
    /// picks), coloured as [`colors`] says.
    pub shapes: bool,
    /// Every joint but the mouse joint: body A's centre to its anchor, anchor to anchor,
    /// body B's anchor to its centre, a point at each anchor (a distance joint: its anchors
    /// only). The mouse joint: its target and a line to the point it pulls.
    pub joints: bool,
    /// A slider's axis and limits, a hinge's limits as spokes.
    pub joint_extras: bool,
    /// Each joint's reaction force on body B as a line from its anchor: a pixel per newton,
    /// at most 100 pixels.
    pub joint_forces: bool,
    /// Every shape's fat bounding box, as the broad phase holds it.
    pub aabbs: bool,
    /// The broad phase tree's inner nodes.
    pub tree: bool,
    /// Each moving body's centre of mass, as a frame.
    pub mass: bool,
    /// Contact points, touching and speculative in two colours.
    pub contacts: bool,
    /// Each contact point's normal.
    pub contact_normals: bool,
    /// Each touching contact's constraint-graph colour ([`graph_color`]).
    pub graph_colors: bool,
    /// Each chain segment's pushing side, a tick from its middle.
    pub chain_normals: bool,
    /// Only shapes, boxes and contacts that meet this box (the view); `None`: all.
    pub bounds: Option<Aabb>,
    /// Metres per pixel of the view: points, ticks and axes are sized in pixels through it,
    /// so they read the same at every zoom.
    pub pixel: f32,
}

impl Default for DrawOptions {
    fn default() -> Self {
        Self {
            shapes: true,
            joints: true,
            joint_extras: false,
            joint_forces: false,
            aabbs: false,
            tree: false,
            mass: false,
            contacts: false,
            contact_normals: false,
            graph_colors: false,
            chain_normals: false,
            bounds: None,
            pixel: 0.02,
        }
    }
}

impl DrawOptions {
    /// Nothing: the start for an application that turns on one layer at a time.
    pub fn nothing() -> Self {
        Self {
            shapes: false,
            joints: false,
            ..Self::default()
        }
    }

    fn sees(&self, aabb: &Aabb) -> bool {
        self.bounds.is_none_or(|b| b.overlaps(aabb))
    }

    fn sees_point(&self, p: Vec2) -> bool {
        self.sees(&Aabb { min: p, max: p })
    }
}

/// # Debug drawing
///
/// ```
/// use tumble_physics::{BodyDef, DebugDraw, DrawOptions, ShapeDef, Vec2, World};
///
/// /// Counts the lines it is given: all a line renderer needs to write.
/// struct Lines(usize);
/// impl DebugDraw for Lines {
///     fn draw_segment(&mut self, _p1: Vec2, _p2: Vec2, _color: [f32; 4]) {
///         self.0 += 1;
///     }
/// }
///
/// let mut world = World::default();
/// world
///     .create_body(&BodyDef::new(ShapeDef::Box { half_extents: [0.5, 0.5], radius: 0.0 }))
///     .unwrap();
/// let mut lines = Lines(0);
/// world.draw(&mut lines, &DrawOptions::default());
/// assert_eq!(lines.0, 4, "a box's outline");
/// ```
impl World {
    /// Draws the world through `draw`: shapes, joints, then the layers `options` turns on
    /// (boxes, the tree, centres of mass, contacts, graph colours, chain sides), each in the
    /// world's fixed order, so the same world draws the same calls.
    pub fn draw<D: DebugDraw + ?Sized>(&self, draw: &mut D, options: &DrawOptions) {
        let px = options.pixel;
        if options.shapes {
            self.draw_shapes(draw, options);
        }
        if options.joints {
            for id in self.joint_ids() {
                self.draw_joint(draw, id, options);
            }
        }
        if options.aabbs {
            for view in self.drawn_shapes(options) {
                let color = match self.body(view.body).map_or(BodyKind::Static, |b| b.kind) {
                    BodyKind::Static => colors::AABB_STATIC,
                    BodyKind::Kinematic => colors::AABB_KINEMATIC,
                    BodyKind::Dynamic => colors::AABB_DYNAMIC,
                };
                draw.draw_aabb(view.fat_aabb, color);
            }
        }
        if options.tree {
            for node in self.broad_phase().nodes() {
                if !node.is_leaf() && options.sees(&node.aabb) {
                    draw.draw_aabb(node.aabb, colors::TREE);
                }
            }
        }
        if options.mass {
            for (_, b) in self.bodies() {
                if b.kind != BodyKind::Static && options.sees_point(b.position) {
                    let frame = Transform {
                        p: b.position,
                        q: b.rotation,
                    };
                    draw.draw_transform(frame, 10.0 * px);
                }
            }
        }
        if options.contacts || options.contact_normals {
            for contact in self.contacts() {
                let m = contact.manifold;
                for (point, &at) in m.points().iter().zip(contact.world_points()) {
                    if !options.sees_point(at) {
                        continue;
                    }
                    if options.contacts {
                        let c = if point.separation <= 0.0 {
                            colors::TOUCHING
                        } else {
                            colors::SPECULATIVE
                        };
                        draw.draw_point(at, 5.0 * px, c);
                    }
                    if options.contact_normals {
                        draw.draw_segment(at, at + m.normal * 18.0 * px, colors::NORMAL);
                    }
                }
            }
        }
        if options.graph_colors {
            let colored = self.contact_colors();
            if !colored.is_empty() {
                let contacts: Vec<_> = self.contacts().collect();
                for (index, color) in colored {
                    let Some(contact) = contacts.get(index) else {
                        continue;
                    };
                    for &at in contact.world_points() {
                        if options.sees_point(at) {
                            draw.draw_point(at, 7.0 * px, graph_color(color));
                        }
                    }
                }
            }
        }
        if options.chain_normals {
            for view in self.drawn_shapes(options) {
                if let Shape::ChainSegment(chain) = view.shape {
                    let a = view.transform.apply(chain.segment.point1);
                    let b = view.transform.apply(chain.segment.point2);
                    let side = Vec2::new(b.y - a.y, a.x - b.x).normalize_or_zero();
                    let mid = (a + b) * 0.5;
                    draw.draw_segment(mid, mid + side * 12.0 * px, colors::CHAIN_SIDE);
                }
            }
        }
    }

    /// The shapes drawn: live, of an enabled body (a disabled one is out of the world, as
    /// Box2D's leave its broad phase), meeting the bounds.
    fn drawn_shapes<'w>(
        &'w self,
        options: &'w DrawOptions,
    ) -> impl Iterator<Item = super::ShapeView<'w>> + 'w {
        self.shapes().filter(move |v| {
            !self.shapes.records[v.id.index as usize].disabled && options.sees(&v.fat_aabb)
        })
    }

    fn draw_shapes<D: DebugDraw + ?Sized>(&self, draw: &mut D, options: &DrawOptions) {
        // A body's shapes are mostly neighbours: its state is read once per run of them.
        let mut last: Option<(BodyId, BodyKind, bool, bool)> = None;
        for view in self.drawn_shapes(options) {
            let (kind, awake, bullet) = match last {
                Some((body, kind, awake, bullet)) if body == view.body => (kind, awake, bullet),
                _ => {
                    let (kind, awake, bullet) = self
                        .body(view.body)
                        .map_or((BodyKind::Static, true, false), |b| {
                            (b.kind, b.awake, b.bullet)
                        });
                    last = Some((view.body, kind, awake, bullet));
                    (kind, awake, bullet)
                }
            };
            let info = ShapeDraw {
                shape: view.id,
                body: view.body,
                kind,
                awake,
                sensor: view.sensor,
                bullet,
            };
            let color = if view.sensor {
                colors::SENSOR
            } else {
                match kind {
                    BodyKind::Static => colors::STATIC,
                    BodyKind::Kinematic => colors::KINEMATIC,
                    BodyKind::Dynamic if bullet => colors::BULLET,
                    BodyKind::Dynamic if awake => colors::AWAKE,
                    BodyKind::Dynamic => colors::ASLEEP,
                }
            };
            let xf = view.transform;
            match view.shape {
                Shape::Circle(c) => draw.draw_circle(xf, c.radius, color, &info),
                Shape::Polygon(p) => draw.draw_polygon(xf, p.points(), p.radius, color, &info),
                Shape::Capsule(c) => {
                    draw.draw_capsule(xf, c.center1, c.center2, c.radius, color, &info);
                }
                Shape::Segment(s) => {
                    draw.draw_segment_shape(xf.apply(s.point1), xf.apply(s.point2), color, &info);
                }
                Shape::ChainSegment(s) => {
                    let seg = &s.segment;
                    draw.draw_segment_shape(
                        xf.apply(seg.point1),
                        xf.apply(seg.point2),
                        color,
                        &info,
                    );
                }
            }
        }
    }

    fn draw_joint<D: DebugDraw + ?Sized>(&self, draw: &mut D, id: JointId, options: &DrawOptions) {
        let px = options.pixel;
        let (Ok(joint), Ok([pa, pb]), Ok(bodies)) = (
            self.joint(id),
            self.joint_anchors(id),
            self.joint_bodies(id),
        ) else {
            return;
        };
        let (Ok(body_a), Ok(body_b)) = (self.body(bodies[0]), self.body(bodies[1])) else {
            return;
        };
        let disabled = |b: BodyId| self.bodies.records[b.index as usize].disabled;
        if disabled(bodies[0]) || disabled(bodies[1]) {
            return;
        }
        let color = colors::JOINT;
        match &joint.kind {
            JointKind::Filter => return,
            JointKind::Mouse(m) => {
                draw.draw_point(m.target, 6.0 * px, [1.0, 1.0, 1.0, 0.9]);
                draw.draw_segment(m.target, pb, [1.0, 1.0, 1.0, 0.9]);
                return;
            }
            JointKind::Distance(_) => draw.draw_segment(pa, pb, color),
            _ => {
                draw.draw_segment(body_a.position, pa, color);
                draw.draw_segment(pa, pb, color);
                draw.draw_segment(body_b.position, pb, color);
            }
        }
        draw.draw_point(pa, 5.0 * px, color);
        draw.draw_point(pb, 5.0 * px, color);
        if options.joint_extras {
            // A slider's axis (fixed in A) and its limit's ends; a hinge's limit as two
            // spokes from the hinge at the bounds, counted from frame A.
            let frame_a = body_a.rotation.then_from(joint.local_a.q);
            match &joint.kind {
                JointKind::Prismatic(crate::joint::Prismatic { limit, .. })
                | JointKind::Wheel(crate::joint::Wheel { limit, .. }) => {
                    let axis = frame_a.apply(Vec2::X);
                    let reach = 40.0 * px;
                    draw.draw_segment(pa - axis * reach, pa + axis * reach, colors::AXIS);
                    if let Some([lower, upper]) = limit {
                        let across = Vec2::new(-axis.y, axis.x) * 4.0 * px;
                        for end in [pa + axis * *lower, pa + axis * *upper] {
                            draw.draw_segment(end - across, end + across, colors::LIMIT);
                        }
                    }
                }
                JointKind::Revolute(r) => {
                    if let Some([lower, upper]) = r.limit {
                        for angle in [lower, upper] {
                            let spoke = frame_a.then_from(Rot::from_angle(angle));
                            draw.draw_segment(
                                pb,
                                pb + spoke.apply(Vec2::X) * 20.0 * px,
                                colors::LIMIT,
                            );
                        }
                    }
                }
                _ => {}
            }
        }
        if options.joint_forces
            && let Ok((force, _)) = self.joint_reaction(id)
        {
            let len = force.length();
            if len > 0.0 {
                let shown = len.min(100.0) * px;
                draw.draw_segment(pb, pb + force / len * shown, colors::FORCE);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec2;

    use super::*;
    use crate::def::{BodyDef, ShapeDef};
    use crate::joint::JointDef;
    use crate::world::StepSettings;

    /// Only lines: what an application that implements nothing else sees.
    #[derive(Default)]
    struct Lines(Vec<(Vec2, Vec2, Color)>);

    impl DebugDraw for Lines {
        fn draw_segment(&mut self, p1: Vec2, p2: Vec2, color: Color) {
            self.0.push((p1, p2, color));
        }
    }

    fn body(w: &mut World, shape: ShapeDef, x: f32, y: f32, angle: f32) -> BodyId {
        w.create_body(&BodyDef::new(shape).at(x, y).angle(angle))
            .unwrap()
    }

    fn lines_of(w: &World, options: &DrawOptions) -> Vec<(Vec2, Vec2, Color)> {
        let mut lines = Lines::default();
        w.draw(&mut lines, options);
        lines.0
    }

    /// Distance from `p` to the segment from `a` to `b`.
    fn to_segment(p: Vec2, a: Vec2, b: Vec2) -> f32 {
        let e = b - a;
        let t = ((p - a).dot(e) / e.length_squared()).clamp(0.0, 1.0);
        (a + e * t - p).length()
    }

    // Every outline point must lie on the shape's boundary. The tolerance, 2e-5 m, is a few
    // f32 roundings of coordinates of order 5 m (ulp 4.8e-7) through a rotation.
    const ON_BOUNDARY: f32 = 2e-5;

    #[test]
    fn a_line_renderer_sees_every_shape_kind_on_its_outline() {
        let mut w = World::new(StepSettings::default());
        let sharp = ShapeDef::Box {
            half_extents: [1.0, 0.5],
            radius: 0.0,
        };
        body(&mut w, sharp, 2.0, 3.0, 0.3);
        let xf = w.shapes().next().unwrap().transform;
        let box_lines = lines_of(&w, &DrawOptions::default());
        assert_eq!(box_lines.len(), 4);
        let corners = [[-1.0, -0.5], [1.0, -0.5], [1.0, 0.5], [-1.0, 0.5]]
            .map(|[x, y]| xf.apply(Vec2::new(x, y)));
        for (k, &(a, b, color)) in box_lines.iter().enumerate() {
            assert!(
                (a - corners[k]).length() < ON_BOUNDARY,
                "{a} {}",
                corners[k]
            );
            assert!((b - corners[(k + 1) % 4]).length() < ON_BOUNDARY);
            assert_eq!(color, colors::AWAKE);
        }

        let mut w = World::new(StepSettings::default());
        body(&mut w, ShapeDef::Circle { radius: 0.7 }, -1.0, 4.0, 1.0);
        let circle = lines_of(&w, &DrawOptions::default());
        assert_eq!(circle.len(), CIRCLE_SIDES + 1);
        for &(a, b, _) in &circle[..CIRCLE_SIDES] {
            for p in [a, b] {
                assert!(((p - Vec2::new(-1.0, 4.0)).length() - 0.7).abs() < ON_BOUNDARY);
            }
        }
        // The radius line turns with the body.
        let (c, r, _) = circle[CIRCLE_SIDES];
        assert!((r - c - Vec2::new(1f32.cos(), 1f32.sin()) * 0.7).length() < ON_BOUNDARY);

        let capsule = ShapeDef::Capsule {
            center1: [-0.5, 0.0],
            center2: [0.5, 0.0],
            radius: 0.25,
        };
        let rounded = ShapeDef::Box {
            half_extents: [0.5, 0.4],
            radius: 0.1,
        };
        for (shape, core) in [
            (capsule, vec![Vec2::new(-0.5, 0.0), Vec2::new(0.5, 0.0)]),
            (
                rounded,
                vec![
                    Vec2::new(-0.5, -0.4),
                    Vec2::new(0.5, -0.4),
                    Vec2::new(0.5, 0.4),
                    Vec2::new(-0.5, 0.4),
                ],
            ),
        ] {
            let radius = if core.len() == 2 { 0.25 } else { 0.1 };
            let mut w = World::new(StepSettings::default());
            body(&mut w, shape, 3.0, -2.0, -0.7);
            let xf = w.shapes().next().unwrap().transform;
            let core: Vec<Vec2> = core.iter().map(|&p| xf.apply(p)).collect();
            let outline = lines_of(&w, &DrawOptions::default());
            // An edge and an arc of ARC_STEPS pieces per corner.
            assert_eq!(outline.len(), core.len() * (1 + ARC_STEPS));
            for &(a, b, _) in &outline {
                for p in [a, b] {
                    let d = (0..core.len())
                        .map(|k| to_segment(p, core[k], core[(k + 1) % core.len()]))
                        .fold(f32::MAX, f32::min);
                    assert!((d - radius).abs() < ON_BOUNDARY, "{p}: {d}");
                }
            }
            // A closed loop: each line starts where the last ended.
            for k in 0..outline.len() {
                let next = outline[(k + 1) % outline.len()].0;
                assert!((outline[k].1 - next).length() < ON_BOUNDARY);
            }
        }

        let mut w = World::new(StepSettings::default());
        let chain = ShapeDef::Chain {
            points: vec![[-3.0, 0.0], [-1.0, 0.0], [1.0, 0.5], [3.0, 0.0], [5.0, 0.0]],
            looped: false,
        };
        w.create_body(&BodyDef::new(chain).kind(BodyKind::Static))
            .unwrap();
        let segment = ShapeDef::Segment {
            point1: [0.0, 2.0],
            point2: [1.0, 2.0],
        };
        w.create_body(&BodyDef::new(segment).kind(BodyKind::Static))
            .unwrap();
        let lines = lines_of(&w, &DrawOptions::default());
        assert_eq!(lines.len(), w.shape_count());
        assert!(lines.iter().all(|l| l.2 == colors::STATIC));
        assert!(lines.contains(&(Vec2::new(-1.0, 0.0), Vec2::new(1.0, 0.5), colors::STATIC)));
        // Nothing asked, nothing drawn.
        assert!(lines_of(&w, &DrawOptions::nothing()).is_empty());
    }

    /// Fills: counts each solid call and keeps what it was told about the shape.
    #[derive(Default)]
    struct Solids {
        lines: usize,
        solids: Vec<(&'static str, ShapeDraw, Color)>,
        points: Vec<(Vec2, Color)>,
    }

    impl DebugDraw for Solids {
        fn draw_segment(&mut self, _: Vec2, _: Vec2, _: Color) {
            self.lines += 1;
        }
        fn draw_polygon(&mut self, _: Transform, _: &[Vec2], _: f32, c: Color, s: &ShapeDraw) {
            self.solids.push(("polygon", *s, c));
        }
        fn draw_circle(&mut self, _: Transform, _: f32, c: Color, s: &ShapeDraw) {
            self.solids.push(("circle", *s, c));
        }
        fn draw_point(&mut self, p: Vec2, _: f32, c: Color) {
            self.points.push((p, c));
        }
    }

    #[test]
    fn solid_shapes_name_their_body_and_state_and_contacts_and_joints_draw_on_request() {
        let mut w = World::new(StepSettings::default());
        let ground = w
            .create_body(
                &BodyDef::new(ShapeDef::Box {
                    half_extents: [20.0, 0.5],
                    radius: 0.0,
                })
                .kind(BodyKind::Static)
                .at(0.0, -0.5),
            )
            .unwrap();
        let crate_ = body(
            &mut w,
            ShapeDef::Box {
                half_extents: [0.5, 0.5],
                radius: 0.0,
            },
            0.0,
            0.5,
            0.0,
        );
        let ball = body(&mut w, ShapeDef::Circle { radius: 0.3 }, 4.0, 2.0, 0.0);
        w.create_joint(&JointDef::hinge([crate_, ball], [2.0, 1.0]))
            .unwrap();
        for _ in 0..5 {
            w.step(1.0 / 60.0, 4);
        }

        let mut solids = Solids::default();
        w.draw(&mut solids, &DrawOptions::default());
        let kinds: Vec<_> = solids.solids.iter().map(|s| (s.0, s.1.body)).collect();
        assert_eq!(
            kinds,
            [("polygon", ground), ("polygon", crate_), ("circle", ball)]
        );
        assert_eq!(solids.solids[0].2, colors::STATIC);
        assert_eq!(solids.solids[0].1.kind, BodyKind::Static);
        assert!(solids.solids[1].1.awake && !solids.solids[1].1.sensor);
        // The hinge: centre A to anchor, anchor to anchor, anchor to centre B, two anchors.
        assert_eq!(solids.lines, 3);
        assert_eq!(solids.points.len(), 2);

        // The crate rests on the ground: its touching points are drawn, and nothing else
        // touches.
        let options = DrawOptions {
            contacts: true,
            ..DrawOptions::nothing()
        };
        let mut contacts = Solids::default();
        w.draw(&mut contacts, &options);
        let touching: Vec<_> = contacts
            .points
            .iter()
            .filter(|p| p.1 == colors::TOUCHING)
            .collect();
        assert_eq!(touching.len(), 2, "{:?}", contacts.points);
        assert!(
            touching
                .iter()
                .all(|p| p.0.y.abs() < 0.05 && p.0.x.abs() < 0.55)
        );

        // A view over the ball only: one shape drawn.
        let view = DrawOptions {
            bounds: Some(Aabb {
                min: Vec2::new(3.0, 1.0),
                max: Vec2::new(5.0, 3.0),
            }),
            joints: false,
            ..DrawOptions::default()
        };
        let mut culled = Solids::default();
        w.draw(&mut culled, &view);
        assert_eq!(culled.solids.len(), 1);
        assert_eq!(culled.solids[0].1.body, ball);

        // Boxes, centres of mass and graph colours each draw something; the same world
        // draws the same calls.
        let all = DrawOptions {
            aabbs: true,
            tree: true,
            mass: true,
            contact_normals: true,
            graph_colors: true,
            joint_extras: true,
            joint_forces: true,
            chain_normals: true,
            ..DrawOptions::default()
        };
        let first = lines_of(&w, &all);
        assert_eq!(first, lines_of(&w, &all));
        assert!(first.iter().any(|l| l.2 == colors::AABB_DYNAMIC));
        assert!(first.iter().any(|l| l.2 == colors::NORMAL));
        let graph: Vec<Color> = (0..24).map(graph_color).collect();
        assert!(first.iter().any(|l| graph.contains(&l.2)));
        assert!(first.iter().any(|l| l.2 == colors::FORCE));
    }

    #[test]
    fn a_sleeping_body_a_sensor_and_the_mouse_joint_draw_as_box2d_colours_them() {
        let mut w = World::new(StepSettings::default());
        let asleep = w
            .create_body(
                &BodyDef::new(ShapeDef::Circle { radius: 0.5 })
                    .at(0.0, 5.0)
                    .awake(false),
            )
            .unwrap();
        let sensor = w
            .create_body(
                &BodyDef::compound(vec![
                    crate::def::PartDef::new(ShapeDef::Circle { radius: 1.0 }).sensor(true),
                ])
                .kind(BodyKind::Static)
                .at(5.0, 0.0),
            )
            .unwrap();
        let mut solids = Solids::default();
        w.draw(&mut solids, &DrawOptions::default());
        assert_eq!(solids.solids[0].1.body, asleep);
        assert_eq!(solids.solids[0].2, colors::ASLEEP);
        assert!(!solids.solids[0].1.awake);
        assert_eq!(solids.solids[1].1.body, sensor);
        assert!(solids.solids[1].1.sensor);
        assert_eq!(solids.solids[1].2, colors::SENSOR);

        let held = body(&mut w, ShapeDef::Circle { radius: 0.5 }, 0.0, 10.0, 0.0);
        let mouse = w
            .create_mouse_joint(held, Vec2::new(0.0, 10.0), 5.0, 0.7, 100.0)
            .unwrap();
        w.set_mouse_target(mouse, Vec2::new(1.0, 11.0)).unwrap();
        let mut mouse = Solids::default();
        w.draw(
            &mut mouse,
            &DrawOptions {
                shapes: false,
                ..DrawOptions::default()
            },
        );
        // Its target, and one line to the point it pulls.
        assert_eq!(mouse.points.len(), 1);
        assert_eq!(mouse.points[0].0, Vec2::new(1.0, 11.0));
        assert_eq!(mouse.lines, 1);
    }
}
