//! Offscreen rendering with the real pipelines on a real wgpu device (on a machine without a
//! GPU: Mesa's lavapipe, Vulkan on the CPU; `cargo xtask test` installs it). No window.
//!
//! - The frame must match `tests/reference/offscreen.png` within a tolerance: backends and
//!   drivers differ in a fraction of a percent of pixels (edges), so a pixel counts as
//!   different when a channel differs by more than 24, and at most 1% of pixels may.
//!   Regenerate the reference after an intended change with
//!   `TUMBLE_BLESS=1 cargo test --release -p tumble --test offscreen` (and look at it).
//! - A circle's pixels must land where the camera's math puts them.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use tumble_physics::BodyId;

use glam::Vec2;
use tumble_app::camera::Camera;
use tumble_app::render::instances::{dynamic_color, palette};
use tumble_app::render::{Headless, Image, SceneRenderer, Target, encode_frame, read_texture};
use tumble_app::settings::DebugLayers;
use tumble_app::sim::Sim;
use tumble_app::state::View;
use tumble_physics::{BodyDef, BodyKind, SceneDef, ShapeDef};

const WIDTH: u32 = 320;
const HEIGHT: u32 = 200;
/// The circle: body 1, radius 1.5 m at (-3, 2), turned a quarter turn (its orientation line
/// points up).
const CIRCLE_BODY: usize = 1;
const CIRCLE_CENTER: Vec2 = Vec2::new(-3.0, 2.0);
const CIRCLE_RADIUS: f32 = 1.5;

/// A small scene of every shape kind: a static ground, a circle, a turned box, a triangle, a
/// hexagon and a kinematic disc.
fn scene() -> SceneDef {
    let mut scene = SceneDef::new("offscreen");
    scene.push(
        BodyDef::new(ShapeDef::Box {
            half_extents: [7.0, 0.5],
            radius: 0.0,
        })
        .kind(BodyKind::Static)
        .at(0.0, -0.5),
    );
    let mut circle = BodyDef::new(ShapeDef::Circle {
        radius: CIRCLE_RADIUS,
    })
    .at(CIRCLE_CENTER.x, CIRCLE_CENTER.y);
    circle.angle = std::f32::consts::FRAC_PI_2;
    scene.push(circle);
    let mut boxed = BodyDef::new(ShapeDef::Box {
        half_extents: [0.9, 0.6],
        radius: 0.0,
    })
    .at(0.5, 1.2);
    boxed.angle = 0.4;
    scene.push(boxed);
    scene.push(
        BodyDef::new(ShapeDef::Polygon {
            vertices: vec![[-1.0, 0.0], [1.0, 0.0], [0.0, 1.6]],
            radius: 0.0,
        })
        .at(3.5, 0.8),
    );
    let hexagon: Vec<[f32; 2]> = (0..6)
        .map(|k| {
            let a = k as f32 * std::f32::consts::TAU / 6.0;
            [0.7 * a.cos(), 0.7 * a.sin()]
        })
        .collect();
    scene.push(
        BodyDef::new(ShapeDef::Polygon {
            vertices: hexagon,
            radius: 0.0,
        })
        .at(1.0, 4.0),
    );
    scene.push(
        BodyDef::new(ShapeDef::Circle { radius: 0.5 })
            .kind(BodyKind::Kinematic)
            .at(-0.5, 4.2),
    );
    scene
}

fn camera() -> Camera {
    Camera::new(
        Vec2::new(0.0, 2.0),
        25.0,
        Vec2::new(WIDTH as f32, HEIGHT as f32),
    )
}

fn gpu() -> Headless {
    let gpu = pollster::block_on(Headless::new()).unwrap_or_else(|e| {
        panic!(
            "{e:#}\n(the offscreen test needs a wgpu adapter; `cargo xtask test` installs Mesa's \
             lavapipe first)"
        )
    });
    eprintln!("rendering on {} ({:?})", gpu.info.name, gpu.info.backend);
    gpu
}

/// Renders `sim` through `camera` into an offscreen texture and reads it back.
fn render(
    gpu: &Headless,
    sim: &Sim,
    camera: &Camera,
    debug: &DebugLayers,
) -> (Image, SceneRenderer) {
    let format = wgpu::TextureFormat::Rgba8Unorm;
    let mut renderer = SceneRenderer::new(&gpu.device, format);
    let view = View {
        sim,
        camera,
        debug: true,
        dim: 0.0,
    };
    renderer.prepare(&gpu.device, &gpu.queue, Some(view), debug);
    let target = Target::new(
        &gpu.device,
        camera.viewport.x as u32,
        camera.viewport.y as u32,
        format,
    );
    let mut encoder = gpu
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
    encode_frame(&mut encoder, &target.view, &renderer, None);
    gpu.queue.submit([encoder.finish()]);
    let image = read_texture(&gpu.device, &gpu.queue, &target.texture).expect("read back");
    (image, renderer)
}

fn to_u8(rgb: [f32; 3]) -> [u8; 3] {
    rgb.map(|c| (c * 255.0).round() as u8)
}

fn close(a: [u8; 4], b: [u8; 3], tolerance: u8) -> bool {
    (0..3).all(|i| a[i].abs_diff(b[i]) <= tolerance)
}

fn reference_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/reference/offscreen.png")
}

#[test]
fn frame_matches_the_reference_image() {
    let gpu = gpu();
    let sim = Sim::new(Arc::new(scene()), 1).unwrap();
    let (image, renderer) = render(&gpu, &sim, &camera(), &DebugLayers::default());
    // Two shape kinds, no lines: two draw calls.
    assert_eq!(renderer.draw_calls(), 2);
    assert_eq!(renderer.counts()[..2], [2, 4]);

    let path = reference_path();
    if std::env::var_os("TUMBLE_BLESS").is_some() {
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        image.save_png(&path).unwrap();
        eprintln!("wrote {} ({})", path.display(), gpu.info.name);
        return;
    }
    let reference = Image::load_png(&path).unwrap_or_else(|e| {
        panic!("{e:#}; regenerate it with TUMBLE_BLESS=1 cargo test --release -p tumble --test offscreen")
    });
    assert_eq!(
        (reference.width, reference.height),
        (image.width, image.height)
    );
    let differing = image
        .pixels
        .chunks_exact(4)
        .zip(reference.pixels.chunks_exact(4))
        .filter(|(a, b)| (0..3).any(|i| a[i].abs_diff(b[i]) > 24))
        .count();
    let total = (image.width * image.height) as usize;
    let fraction = differing as f64 / total as f64;
    if fraction > 0.01 {
        let out = std::env::temp_dir().join("tumble-offscreen-actual.png");
        let _ = image.save_png(&out);
        panic!(
            "{differing} of {total} pixels ({:.2}%) differ from {} on {} ({:?}); this frame \
             is in {}",
            fraction * 100.0,
            path.display(),
            gpu.info.name,
            gpu.info.backend,
            out.display()
        );
    }
}

#[test]
fn circle_pixels_land_where_the_camera_puts_them() {
    let gpu = gpu();
    let sim = Sim::new(Arc::new(scene()), 1).unwrap();
    let cam = camera();
    let (image, _) = render(&gpu, &sim, &cam, &DebugLayers::default());
    let fill = to_u8(dynamic_color(CIRCLE_BODY));
    let background = to_u8(palette::BACKGROUND);
    let px = |p: Vec2| {
        let s = cam.world_to_screen(p);
        // The pixel whose centre is nearest.
        image.get(s.x.floor() as u32, s.y.floor() as u32)
    };
    let r = CIRCLE_RADIUS;
    // Inside, away from the outline and the orientation line (which points up, +y): fill.
    for d in [
        Vec2::new(0.5, 0.0),
        Vec2::new(-0.7, -0.5),
        Vec2::new(0.0, -0.8),
        Vec2::new(-1.1, 0.3),
    ] {
        let got = px(CIRCLE_CENTER + d);
        assert!(close(got, fill, 2), "inside at {d}: {got:?}, want {fill:?}");
    }
    // Just outside the edge, all around: background.
    for k in 0..16 {
        let a = k as f32 * std::f32::consts::TAU / 16.0;
        let d = Vec2::new(a.cos(), a.sin()) * (r + 3.0 / cam.pixels_per_metre);
        let got = px(CIRCLE_CENTER + d);
        assert!(close(got, background, 2), "outside at {d}: {got:?}");
    }
    // The edge is where the camera says: along the x axis the fill ends within a pixel of
    // centre ± radius.
    let s = cam.world_to_screen(CIRCLE_CENTER);
    let row = s.y.floor() as u32;
    let covered: Vec<u32> = (0..WIDTH)
        .filter(|&x| !close(image.get(x, row), background, 8))
        .filter(|&x| (x as f32 - s.x).abs() < 2.0 * r * cam.pixels_per_metre)
        .collect();
    let (first, last) = (*covered.first().unwrap(), *covered.last().unwrap());
    let radius_px = r * cam.pixels_per_metre;
    assert!(
        (first as f32 - (s.x - radius_px)).abs() <= 1.5,
        "left edge {first}, centre {s}"
    );
    assert!(
        (last as f32 + 1.0 - (s.x + radius_px)).abs() <= 1.5,
        "right edge {last}, centre {s}"
    );
    // The orientation line: the body is turned a quarter turn, so it runs from the centre up;
    // it is drawn darker than the fill.
    let on_line = px(CIRCLE_CENTER + Vec2::new(0.0, 0.7 * r));
    assert!(
        on_line[..3].iter().zip(fill).all(|(&a, b)| a < b),
        "line pixel {on_line:?} not darker than {fill:?}"
    );
}

#[test]
fn debug_lines_are_one_more_draw_call_and_buffers_grow_geometrically() {
    let gpu = gpu();
    let mut sim = Sim::load("large_pyramid", 1).unwrap();
    for _ in 0..2 {
        sim.single_step();
    }
    let cam = Camera::new(
        Vec2::new(0.0, 50.0),
        6.0,
        Vec2::new(WIDTH as f32, HEIGHT as f32),
    );
    let debug = DebugLayers {
        contacts: true,
        aabbs: true,
        tree: true,
        graph_colors: true,
        center_of_mass: true,
        normals: true,
        grid: true,
        color_by_speed: false,
        islands: false,
        joint_forces: true,
    };
    let (image, renderer) = render(&gpu, &sim, &cam, &debug);
    // Polygons and lines; no circles in this scene.
    assert_eq!(renderer.draw_calls(), 2);
    let [circles, polygons, lines] = renderer.counts();
    assert_eq!(circles, 0);
    assert_eq!(polygons as usize, sim.world.body_count());
    assert!(lines > 1000);
    // Buffers hold what was drawn, in power-of-two sizes.
    let caps = renderer.buffer_capacities();
    assert!(caps[1] >= u64::from(polygons) * 120 && caps[1].is_power_of_two());
    assert!(caps[2] >= u64::from(lines) * 24 && caps[2].is_power_of_two());
    // Something was drawn besides the background.
    let background = to_u8(palette::BACKGROUND);
    let drawn = image
        .pixels
        .chunks_exact(4)
        .filter(|p| !close([p[0], p[1], p[2], p[3]], background, 4))
        .count();
    assert!(drawn > 1000, "{drawn} pixels drawn");
}

#[test]
fn every_part_of_a_compound_body_is_drawn_and_a_sleeping_one_faded() {
    use tumble_app::render::instances::asleep;
    use tumble_physics::PartDef;
    let gpu = gpu();
    // One dynamic body of two parts, a box right of its origin and a disc left of it; then
    // the same body asleep beside it.
    let body = |x: f32, awake: bool| {
        BodyDef::compound(vec![
            PartDef::new(ShapeDef::Box {
                half_extents: [0.6, 0.6],
                radius: 0.0,
            })
            .at(1.2, 0.0, 0.0),
            PartDef::new(ShapeDef::Circle { radius: 0.6 }).at(-1.2, 0.0, 0.0),
        ])
        .at(x, 0.0)
        .awake(awake)
    };
    let mut scene = SceneDef::new("compound");
    scene.sleep = true;
    scene.push(body(-2.5, true));
    scene.push(body(2.5, false));
    let sim = Sim::new(Arc::new(scene), 1).unwrap();
    assert!(
        sim.world.is_awake(BodyId::scene(0)).unwrap()
            && !sim.world.is_awake(BodyId::scene(1)).unwrap()
    );
    let cam = Camera::new(Vec2::ZERO, 25.0, Vec2::new(WIDTH as f32, HEIGHT as f32));
    let (image, renderer) = render(&gpu, &sim, &cam, &DebugLayers::default());
    // Two bodies, four shapes: two circles, two polygons.
    assert_eq!(renderer.counts()[..2], [2, 2]);
    let px = |p: Vec2| {
        let s = cam.world_to_screen(p);
        image.get(s.x.floor() as u32, s.y.floor() as u32)
    };
    let background = to_u8(palette::BACKGROUND);
    for (index, x) in [(0, -2.5f32), (1, 2.5)] {
        let fill = if index == 0 {
            dynamic_color(index)
        } else {
            asleep(dynamic_color(index))
        };
        let fill = to_u8(fill);
        // Each part, off its orientation line (the disc's runs right from its centre).
        let box_px = px(Vec2::new(x + 1.2, -0.3));
        assert!(
            close(box_px, fill, 2),
            "body {index} box: {box_px:?}, want {fill:?}"
        );
        let disc_px = px(Vec2::new(x - 1.2, -0.3));
        assert!(
            close(disc_px, fill, 2),
            "body {index} disc: {disc_px:?}, want {fill:?}"
        );
        // Between the parts (the body's origin) nothing is drawn.
        let gap = px(Vec2::new(x, 0.0));
        assert!(close(gap, background, 2), "body {index} origin: {gap:?}");
    }
    // The sleeping body is not drawn in its awake colour.
    let faded = px(Vec2::new(3.7, -0.3));
    assert!(!close(faded, to_u8(dynamic_color(1)), 8), "{faded:?}");
}

#[test]
fn capsules_and_rounded_boxes_are_round_and_segments_are_lines() {
    use tumble_physics::PartDef;
    let gpu = gpu();
    // A capsule (core ±1 m, radius 0.5) left, a box of half size 0.6 rounded by 0.3 right,
    // both asleep-free and still (no gravity); under them a static segment and a chain.
    let mut scene = SceneDef::new("rounded");
    scene.gravity = [0.0, 0.0];
    scene.push(
        BodyDef::new(ShapeDef::Capsule {
            center1: [-1.0, 0.0],
            center2: [1.0, 0.0],
            radius: 0.5,
        })
        .at(-2.5, 1.0),
    );
    scene.push(
        BodyDef::new(ShapeDef::Box {
            half_extents: [0.6, 0.6],
            radius: 0.3,
        })
        .at(2.5, 1.0),
    );
    scene.push(
        BodyDef::compound(vec![
            PartDef::new(ShapeDef::Segment {
                point1: [-5.0, -1.0],
                point2: [5.0, -1.0],
            }),
            PartDef::new(ShapeDef::Chain {
                points: vec![[5.0, -2.0], [2.0, -2.0], [-2.0, -2.5], [-5.0, -2.0]],
                looped: false,
            }),
        ])
        .kind(BodyKind::Static),
    );
    let sim = Sim::new(Arc::new(scene), 1).unwrap();
    let cam = Camera::new(Vec2::ZERO, 25.0, Vec2::new(WIDTH as f32, HEIGHT as f32));
    let (image, renderer) = render(&gpu, &sim, &cam, &DebugLayers::default());
    // The capsule and the rounded box through the polygon pipeline; the segment and the
    // chain's one segment as lines: two draw calls.
    let [circles, polygons, lines] = renderer.counts();
    assert_eq!((circles, polygons, lines), (0, 2, 4));
    assert_eq!(renderer.draw_calls(), 2);
    let px = |p: Vec2| {
        let s = cam.world_to_screen(p);
        image.get(s.x.floor() as u32, s.y.floor() as u32)
    };
    let background = to_u8(palette::BACKGROUND);
    for (index, centre, inside, outside) in [
        // The capsule: 1.35 m out along its core is inside its end cap (0.15 m, 4 px, from
        // the edge); near its bounding box's corner, (1.4, 0.44) out, is 0.6 m from the cap's
        // centre (2.4 px beyond the 0.5 m radius): bare, where a box would be drawn.
        (
            0,
            Vec2::new(-2.5, 1.0),
            [Vec2::new(1.35, 0.0), Vec2::new(0.0, 0.38)],
            [Vec2::new(1.4, 0.44), Vec2::new(-1.4, -0.44)],
        ),
        // The rounded box: 0.78 m out along an axis is inside (the edge at 0.6 + 0.3 is 3 px
        // away); (0.87, 0.87) out is 0.38 m from the core's corner (2 px beyond the
        // rounding), inside the bounding box: bare.
        (
            1,
            Vec2::new(2.5, 1.0),
            [Vec2::new(0.78, 0.0), Vec2::new(0.0, -0.78)],
            [Vec2::new(0.87, 0.87), Vec2::new(-0.87, -0.87)],
        ),
    ] {
        let fill = to_u8(dynamic_color(index));
        for d in inside {
            let got = px(centre + d);
            assert!(
                close(got, fill, 12),
                "body {index} at {d}: {got:?}, want {fill:?}"
            );
        }
        for d in outside {
            let got = px(centre + d);
            assert!(
                close(got, background, 12),
                "body {index} at {d} should be bare: {got:?}"
            );
        }
    }
    // The segment's line crosses x = 0 at y = -1.
    let s = cam.world_to_screen(Vec2::new(0.0, -1.0));
    let column: Vec<[u8; 4]> = (s.y as u32 - 2..=s.y as u32 + 2)
        .map(|y| image.get(s.x as u32, y))
        .collect();
    assert!(
        column.iter().any(|p| !close(*p, background, 12)),
        "no line at the segment: {column:?}"
    );
}

#[test]
fn joints_are_drawn_between_their_anchors() {
    use tumble_physics::JointDef;
    let gpu = gpu();
    // Two discs 6 m apart on a distance joint, no gravity: the joint's line crosses x = 0 at
    // y = 0, where there is no body.
    let mut scene = SceneDef::new("joined");
    scene.gravity = [0.0, 0.0];
    let a = scene.push(BodyDef::new(ShapeDef::Circle { radius: 0.3 }).at(-3.0, 0.0));
    let b = scene.push(BodyDef::new(ShapeDef::Circle { radius: 0.3 }).at(3.0, 0.0));
    scene.joints.push(JointDef::Distance {
        force_threshold: f32::INFINITY,
        torque_threshold: f32::INFINITY,
        bodies: [a, b].map(BodyId::scene),
        anchors: [[-3.0, 0.0], [3.0, 0.0]],
        length: None,
        limit: None,
        spring: None,
        collide_connected: false,
    });
    let sim = Sim::new(Arc::new(scene), 1).unwrap();
    let cam = Camera::new(Vec2::ZERO, 25.0, Vec2::new(WIDTH as f32, HEIGHT as f32));
    let (image, renderer) = render(&gpu, &sim, &cam, &DebugLayers::default());
    let [circles, _, lines] = renderer.counts();
    assert_eq!(circles, 2);
    assert!(lines > 0, "no joint drawn");
    let background = to_u8(palette::BACKGROUND);
    let s = cam.world_to_screen(Vec2::new(0.0, 0.0));
    let column: Vec<[u8; 4]> = (s.y as u32 - 2..=s.y as u32 + 2)
        .map(|y| image.get(s.x as u32, y))
        .collect();
    assert!(
        column.iter().any(|p| !close(*p, background, 12)),
        "no line along the joint: {column:?}"
    );
    // Half way up the screen's left edge nothing is drawn: the line is the joint's.
    let edge = cam.world_to_screen(Vec2::new(0.0, 5.0));
    assert!(close(
        image.get(edge.x as u32, edge.y as u32),
        background,
        12
    ));
}
