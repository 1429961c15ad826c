//! Times the scene renderer alone, offscreen (no window, no egui, no physics): builds the
//! instances of a scene's bodies, draws them into a 1280x800 texture and waits for the GPU,
//! N times.
//!
//! `cargo run --release -p tumble --example render_bench -- [SCENE] [FRAMES]`
//! (default: many_pyramids, 60 frames). On a machine without a GPU this is Mesa's lavapipe.

use std::time::Instant;

use glam::Vec2;
use tumble_app::camera::{Camera, world_bounds};
use tumble_app::render::{Headless, SceneRenderer, Target, encode_frame};
use tumble_app::settings::DebugLayers;
use tumble_app::sim::Sim;
use tumble_app::state::View;

fn main() -> anyhow::Result<()> {
    let mut args = std::env::args().skip(1);
    let scene = args.next().unwrap_or_else(|| "many_pyramids".into());
    let frames: u32 = args.next().map_or(Ok(60), |s| s.parse())?;
    let gpu = pollster::block_on(Headless::new())?;
    let (width, height) = (1280u32, 800u32);
    let format = wgpu::TextureFormat::Rgba8Unorm;
    let sim = Sim::load(&scene, 1)?;
    let mut camera = Camera::new(Vec2::ZERO, 1.0, Vec2::new(width as f32, height as f32));
    camera.fit(world_bounds(&sim.world), (Vec2::ZERO, camera.viewport));
    let mut renderer = SceneRenderer::new(&gpu.device, format);
    let target = Target::new(&gpu.device, width, height, format);
    let debug = DebugLayers::default();
    let mut times = Vec::with_capacity(frames as usize);
    for _ in 0..frames {
        let start = Instant::now();
        let view = View {
            sim: &sim,
            camera: &camera,
            debug: true,
            dim: 0.0,
        };
        renderer.prepare(&gpu.device, &gpu.queue, Some(view), &debug);
        let mut encoder = gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
        encode_frame(&mut encoder, &target.view, &renderer, None);
        gpu.queue.submit([encoder.finish()]);
        gpu.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| anyhow::anyhow!("{e}"))?;
        times.push(start.elapsed().as_secs_f64() * 1000.0);
    }
    times.sort_by(f64::total_cmp);
    let mean = times.iter().sum::<f64>() / times.len() as f64;
    println!(
        "{scene}: {} bodies, {frames} frames at {width}x{height} on {} ({:?}): \
         mean {mean:.2} ms, median {:.2} ms, {} draw calls",
        sim.world.body_count(),
        gpu.info.name,
        gpu.info.backend,
        times[times.len() / 2],
        renderer.draw_calls()
    );
    Ok(())
}
