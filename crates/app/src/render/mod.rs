//! Drawing: the scene renderer (our own pipelines: one draw call per shape kind, one for the
//! debug lines), the frame's render pass with egui on top, device setup with or without a
//! window, and reading a frame back into an image (screenshots and the offscreen test).

pub mod instances;
pub mod pipeline;

use anyhow::{Context, Result, anyhow, bail};
use bytemuck::{Pod, Zeroable};

use instances::palette;
pub use instances::{Coloring, Instances, hsv};
use pipeline::Pipelines;

use crate::camera::Camera;
use crate::settings::DebugLayers;
use crate::sim::Sim;

/// What the renderer draws for a state: a world seen through a camera.
#[derive(Clone, Copy)]
pub struct View<'a> {
    /// The simulation to draw.
    pub sim: &'a Sim,
    /// Where to look.
    pub camera: &'a Camera,
    /// Whether the debug-draw settings apply (not for the intro's and menu's backdrop).
    pub debug: bool,
    /// How much to dim the world (0: not at all, 1: black), for backdrops.
    pub dim: f32,
}

/// The camera as the shaders read it (32 bytes, std140-compatible).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct CameraUniform {
    /// The world point at the viewport's centre.
    pub center: [f32; 2],
    /// Clip units per metre.
    pub clip_scale: [f32; 2],
    /// Pixels per metre.
    pub pixels_per_metre: f32,
    /// Padding to 32 bytes.
    pub _pad: [f32; 3],
}

impl CameraUniform {
    /// The uniform for a camera.
    pub fn new(camera: &Camera) -> Self {
        Self {
            center: camera.center.to_array(),
            clip_scale: camera.clip_scale().to_array(),
            pixels_per_metre: camera.pixels_per_metre,
            _pad: [0.0; 3],
        }
    }
}

/// A GPU buffer that grows geometrically (to the next power of two at least twice its
/// size), so a scene that keeps adding bodies reallocates a logarithmic number of times.
pub struct GrowBuffer {
    buffer: wgpu::Buffer,
    capacity: u64,
    usage: wgpu::BufferUsages,
    label: &'static str,
}

impl GrowBuffer {
    /// An empty buffer of `initial` bytes.
    pub fn new(
        device: &wgpu::Device,
        label: &'static str,
        usage: wgpu::BufferUsages,
        initial: u64,
    ) -> Self {
        let capacity = initial.max(256).next_power_of_two();
        Self {
            buffer: Self::create(device, label, usage, capacity),
            capacity,
            usage,
            label,
        }
    }

    fn create(
        device: &wgpu::Device,
        label: &'static str,
        usage: wgpu::BufferUsages,
        size: u64,
    ) -> wgpu::Buffer {
        device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size,
            usage: usage | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        })
    }

    /// Uploads `data`, growing first if it does not fit.
    pub fn upload(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, data: &[u8]) {
        let needed = data.len() as u64;
        if needed > self.capacity {
            self.capacity = needed.max(self.capacity * 2).next_power_of_two();
            self.buffer = Self::create(device, self.label, self.usage, self.capacity);
        }
        if !data.is_empty() {
            queue.write_buffer(&self.buffer, 0, data);
        }
    }

    /// The buffer.
    pub fn buffer(&self) -> &wgpu::Buffer {
        &self.buffer
    }

    /// Its size in bytes.
    pub fn capacity(&self) -> u64 {
        self.capacity
    }
}

/// Draws a world: bodies, then debug lines.
pub struct SceneRenderer {
    pipelines: Pipelines,
    camera_buffer: wgpu::Buffer,
    camera_group: wgpu::BindGroup,
    circles: GrowBuffer,
    polygons: GrowBuffer,
    lines: GrowBuffer,
    counts: [u32; 3],
    instances: Instances,
    /// The colour the frame is cleared to (the background, dimmed for backdrops).
    pub clear: wgpu::Color,
}

impl SceneRenderer {
    /// The pipelines and buffers for targets of `format`.
    pub fn new(device: &wgpu::Device, format: wgpu::TextureFormat) -> Self {
        let pipelines = Pipelines::new(device, format);
        let camera_buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("camera"),
            size: size_of::<CameraUniform>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let camera_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("camera"),
            layout: &pipelines.camera_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: camera_buffer.as_entire_binding(),
            }],
        });
        let vertex = wgpu::BufferUsages::VERTEX;
        Self {
            circles: GrowBuffer::new(device, "circles", vertex, 1 << 14),
            polygons: GrowBuffer::new(device, "polygons", vertex, 1 << 16),
            lines: GrowBuffer::new(device, "lines", vertex, 1 << 14),
            pipelines,
            camera_buffer,
            camera_group,
            counts: [0; 3],
            instances: Instances::default(),
            clear: background(0.0),
        }
    }

    /// Builds this frame's instances from `view` and uploads them (nothing to draw without a
    /// view: the frame is only cleared).
    pub fn prepare(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        view: Option<View<'_>>,
        debug: &DebugLayers,
    ) {
        self.instances.clear();
        let mut camera = Camera::new(glam::Vec2::ZERO, 1.0, glam::Vec2::ONE);
        self.clear = background(0.0);
        if let Some(view) = view {
            camera = *view.camera;
            self.clear = background(view.dim);
            if debug.grid && view.debug {
                self.instances.add_grid(&camera);
            }
            let world = &view.sim.world;
            let coloring = if view.debug {
                Coloring::of(debug)
            } else {
                Coloring::Id
            };
            self.instances.add_bodies(world, coloring, view.dim);
            self.instances.add_bullets(world, &camera);
            self.instances
                .add_joints(world, debug.joint_forces && view.debug, &camera);
            if let Some(controller) = &view.sim.controller {
                self.instances.add_sample(world, controller);
            }
            if view.debug {
                self.instances.add_debug(world, debug, &camera);
                if let Some(drag) = &view.sim.drag {
                    self.instances.add_drag(world, drag, &camera);
                }
                if let Some((from, to)) = view.sim.ray {
                    self.instances.add_ray(world, from, to, &camera);
                }
            }
        }
        queue.write_buffer(
            &self.camera_buffer,
            0,
            bytemuck::bytes_of(&CameraUniform::new(&camera)),
        );
        let inst = &self.instances;
        self.circles
            .upload(device, queue, bytemuck::cast_slice(&inst.circles));
        self.polygons
            .upload(device, queue, bytemuck::cast_slice(&inst.polygons));
        self.lines
            .upload(device, queue, bytemuck::cast_slice(&inst.lines));
        self.counts = [
            inst.circles.len() as u32,
            inst.polygons.len() as u32,
            inst.lines.len() as u32,
        ];
    }

    /// Records the draws: circles, polygons (one instanced draw each), then lines. Kinds
    /// with nothing to draw are skipped.
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>) {
        let [circles, polygons, lines] = self.counts;
        pass.set_bind_group(0, &self.camera_group, &[]);
        if circles > 0 {
            pass.set_pipeline(&self.pipelines.circles);
            pass.set_vertex_buffer(0, self.circles.buffer().slice(..));
            pass.draw(0..6, 0..circles);
        }
        if polygons > 0 {
            pass.set_pipeline(&self.pipelines.polygons);
            pass.set_vertex_buffer(0, self.polygons.buffer().slice(..));
            pass.draw(0..6, 0..polygons);
        }
        if lines > 0 {
            pass.set_pipeline(&self.pipelines.lines);
            pass.set_vertex_buffer(0, self.lines.buffer().slice(..));
            pass.draw(0..lines, 0..1);
        }
    }

    /// Draw calls the last [`SceneRenderer::draw`] recorded.
    pub fn draw_calls(&self) -> u32 {
        self.counts.iter().filter(|&&n| n > 0).count() as u32
    }

    /// Instances of each kind this frame: (circles, polygons, line vertices).
    pub fn counts(&self) -> [u32; 3] {
        self.counts
    }

    /// Bytes the instance buffers hold, for the geometric-growth test.
    pub fn buffer_capacities(&self) -> [u64; 3] {
        [
            self.circles.capacity(),
            self.polygons.capacity(),
            self.lines.capacity(),
        ]
    }

    /// The CPU-side instances of the last frame.
    pub fn instances(&self) -> &Instances {
        &self.instances
    }
}

/// The background colour, darkened by `dim`.
pub fn background(dim: f32) -> wgpu::Color {
    let k = f64::from(1.0 - dim.clamp(0.0, 1.0));
    let [r, g, b] = palette::BACKGROUND;
    wgpu::Color {
        r: f64::from(r) * k,
        g: f64::from(g) * k,
        b: f64::from(b) * k,
        a: 1.0,
    }
}

/// egui's part of a frame: already tessellated, buffers already updated.
pub struct EguiFrame<'a> {
    /// egui's renderer.
    pub renderer: &'a egui_wgpu::Renderer,
    /// The tessellated UI.
    pub primitives: &'a [egui::ClippedPrimitive],
    /// Size and scale.
    pub screen: &'a egui_wgpu::ScreenDescriptor,
}

/// Records one frame into `target`: clear, the world, then egui over it, in one render pass.
pub fn encode_frame(
    encoder: &mut wgpu::CommandEncoder,
    target: &wgpu::TextureView,
    scene: &SceneRenderer,
    egui: Option<&EguiFrame<'_>>,
) {
    let mut pass = encoder
        .begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("frame"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: target,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(scene.clear),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        })
        .forget_lifetime();
    scene.draw(&mut pass);
    if let Some(egui) = egui {
        egui.renderer
            .render(&mut pass, egui.primitives, egui.screen);
    }
}

/// Picks a surface format egui draws correctly in: a non-sRGB 8-bit format (egui blends in
/// gamma space), else the first one offered.
pub fn pick_format(formats: &[wgpu::TextureFormat]) -> Option<wgpu::TextureFormat> {
    use wgpu::TextureFormat as F;
    [F::Bgra8Unorm, F::Rgba8Unorm]
        .into_iter()
        .find(|f| formats.contains(f))
        .or_else(|| formats.iter().copied().find(|f| !f.is_srgb()))
        .or_else(|| formats.first().copied())
}

/// The limits we ask for: what the web build will also get (WebGL2's), raised to what the
/// adapter allows for texture sizes.
pub fn required_limits(adapter: &wgpu::Adapter) -> wgpu::Limits {
    wgpu::Limits::downlevel_webgl2_defaults().using_resolution(adapter.limits())
}

/// A device and queue from `adapter`.
pub async fn request_device(adapter: &wgpu::Adapter) -> Result<(wgpu::Device, wgpu::Queue)> {
    adapter
        .request_device(&wgpu::DeviceDescriptor {
            label: Some("tumble"),
            required_features: wgpu::Features::empty(),
            required_limits: required_limits(adapter),
            ..Default::default()
        })
        .await
        .context("cannot open the graphics device")
}

/// A device with no window (for tests and tools): `WGPU_BACKEND` and friends are honoured.
pub struct Headless {
    /// The device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
    /// What the adapter is (name, backend, driver).
    pub info: wgpu::AdapterInfo,
}

impl Headless {
    /// Opens the first adapter wgpu finds (on a machine without a GPU: Mesa's lavapipe).
    pub async fn new() -> Result<Self> {
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let adapter = instance
            .request_adapter(&wgpu::RequestAdapterOptions::default())
            .await
            .map_err(|e| {
                anyhow!(
                    "no graphics adapter ({e}); on Debian without a GPU install Mesa's \
                     software Vulkan: apt-get install mesa-vulkan-drivers libvulkan1"
                )
            })?;
        let info = adapter.get_info();
        let (device, queue) = request_device(&adapter).await?;
        Ok(Self {
            device,
            queue,
            info,
        })
    }
}

/// An RGBA8 image (row-major, top row first).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// RGBA bytes, `4 * width * height`.
    pub pixels: Vec<u8>,
}

impl Image {
    /// The pixel at (x, y).
    pub fn get(&self, x: u32, y: u32) -> [u8; 4] {
        let i = 4 * (y as usize * self.width as usize + x as usize);
        [
            self.pixels[i],
            self.pixels[i + 1],
            self.pixels[i + 2],
            self.pixels[i + 3],
        ]
    }

    /// Writes the image as PNG.
    pub fn save_png(&self, path: &std::path::Path) -> Result<()> {
        let file = std::fs::File::create(path)
            .with_context(|| format!("cannot create {}", path.display()))?;
        let mut encoder = png::Encoder::new(std::io::BufWriter::new(file), self.width, self.height);
        encoder.set_color(png::ColorType::Rgba);
        encoder.set_depth(png::BitDepth::Eight);
        let mut writer = encoder
            .write_header()
            .with_context(|| format!("cannot write {}", path.display()))?;
        writer
            .write_image_data(&self.pixels)
            .with_context(|| format!("cannot write {}", path.display()))?;
        writer
            .finish()
            .with_context(|| format!("cannot write {}", path.display()))
    }

    /// Reads an 8-bit RGB or RGBA PNG.
    pub fn load_png(path: &std::path::Path) -> Result<Image> {
        let file =
            std::fs::File::open(path).with_context(|| format!("cannot open {}", path.display()))?;
        let decoder = png::Decoder::new(std::io::BufReader::new(file));
        let mut reader = decoder
            .read_info()
            .with_context(|| format!("{}: not a PNG", path.display()))?;
        let size = reader
            .output_buffer_size()
            .ok_or_else(|| anyhow!("{}: image too large", path.display()))?;
        let mut buf = vec![0; size];
        let info = reader
            .next_frame(&mut buf)
            .with_context(|| format!("{}: cannot decode", path.display()))?;
        if info.bit_depth != png::BitDepth::Eight {
            bail!("{}: not an 8-bit PNG", path.display());
        }
        let pixels = match info.color_type {
            png::ColorType::Rgba => buf[..info.buffer_size()].to_vec(),
            png::ColorType::Rgb => buf[..info.buffer_size()]
                .chunks_exact(3)
                .flat_map(|p| [p[0], p[1], p[2], 255])
                .collect(),
            other => bail!("{}: unsupported PNG colour type {other:?}", path.display()),
        };
        Ok(Image {
            width: info.width,
            height: info.height,
            pixels,
        })
    }
}

/// A texture to render into and read back: what the window shows, but offscreen.
pub struct Target {
    /// The texture.
    pub texture: wgpu::Texture,
    /// A view of it for the render pass.
    pub view: wgpu::TextureView,
}

impl Target {
    /// A `width` × `height` texture of `format` that can be rendered to and copied from.
    pub fn new(
        device: &wgpu::Device,
        width: u32,
        height: u32,
        format: wgpu::TextureFormat,
    ) -> Self {
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("offscreen"),
            size: wgpu::Extent3d {
                width: width.max(1),
                height: height.max(1),
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let view = texture.create_view(&wgpu::TextureViewDescriptor::default());
        Self { texture, view }
    }
}

/// Copies a texture (8-bit RGBA or BGRA) back to the CPU as RGBA, waiting for the GPU.
pub fn read_texture(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
) -> Result<Image> {
    use wgpu::TextureFormat as F;
    let format = texture.format();
    let bgra = match format {
        F::Bgra8Unorm | F::Bgra8UnormSrgb => true,
        F::Rgba8Unorm | F::Rgba8UnormSrgb => false,
        other => bail!("cannot read back a texture of format {other:?}"),
    };
    let (width, height) = (texture.width(), texture.height());
    let unpadded = 4 * width;
    let align = wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let padded = unpadded.div_ceil(align) * align;
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size: u64::from(padded) * u64::from(height),
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
        label: Some("readback"),
    });
    encoder.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo {
            texture,
            mip_level: 0,
            origin: wgpu::Origin3d::ZERO,
            aspect: wgpu::TextureAspect::All,
        },
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded),
                rows_per_image: Some(height),
            },
        },
        wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
    );
    queue.submit([encoder.finish()]);
    let slice = buffer.slice(..);
    let (tx, rx) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| anyhow!("waiting for the GPU failed: {e}"))?;
    rx.recv()
        .map_err(|_| anyhow!("the GPU never finished the copy"))?
        .map_err(|e| anyhow!("cannot map the readback buffer: {e}"))?;
    let mut pixels = Vec::with_capacity((unpadded * height) as usize);
    {
        let data = slice
            .get_mapped_range()
            .map_err(|e| anyhow!("cannot read the readback buffer: {e:?}"))?;
        for row in data.chunks(padded as usize).take(height as usize) {
            pixels.extend_from_slice(&row[..unpadded as usize]);
        }
    }
    buffer.unmap();
    if bgra {
        for p in pixels.chunks_exact_mut(4) {
            p.swap(0, 2);
        }
    }
    Ok(Image {
        width,
        height,
        pixels,
    })
}
