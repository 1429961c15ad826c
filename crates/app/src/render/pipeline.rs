//! The render pipelines: circles and polygons from `shaders/shapes.wgsl` (instanced quads,
//! alpha-blended signed-distance shading), and debug lines from `shaders/lines.wgsl`.

use super::instances::{CircleInstance, LineVertex, PolygonInstance};

/// The WGSL of the shape pipelines.
pub const SHAPES_WGSL: &str = include_str!("../../../../shaders/shapes.wgsl");
/// The WGSL of the line pipeline.
pub const LINES_WGSL: &str = include_str!("../../../../shaders/lines.wgsl");

/// The three pipelines and the camera's bind-group layout they share.
pub struct Pipelines {
    /// Group 0: the camera uniform.
    pub camera_layout: wgpu::BindGroupLayout,
    /// Circles: one instance per circle, six vertices each.
    pub circles: wgpu::RenderPipeline,
    /// Polygons: one instance per polygon, six vertices each.
    pub polygons: wgpu::RenderPipeline,
    /// Debug lines: a line list.
    pub lines: wgpu::RenderPipeline,
}

impl Pipelines {
    /// Compiles the shaders and builds the pipelines for targets of `format`.
    pub fn new(device: &wgpu::Device, format: wgpu::TextureFormat) -> Self {
        let camera_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("camera"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            }],
        });
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("scene"),
            bind_group_layouts: &[Some(&camera_layout)],
            immediate_size: 0,
        });
        let shapes = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("shapes.wgsl"),
            source: wgpu::ShaderSource::Wgsl(SHAPES_WGSL.into()),
        });
        let lines = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("lines.wgsl"),
            source: wgpu::ShaderSource::Wgsl(LINES_WGSL.into()),
        });
        let make = |label: &str,
                    module: &wgpu::ShaderModule,
                    vs: &str,
                    fs: &str,
                    buffer: wgpu::VertexBufferLayout<'static>,
                    topology: wgpu::PrimitiveTopology| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(label),
                layout: Some(&layout),
                vertex: wgpu::VertexState {
                    module,
                    entry_point: Some(vs),
                    compilation_options: Default::default(),
                    buffers: &[Some(buffer)],
                },
                primitive: wgpu::PrimitiveState {
                    topology,
                    ..Default::default()
                },
                depth_stencil: None,
                multisample: wgpu::MultisampleState::default(),
                fragment: Some(wgpu::FragmentState {
                    module,
                    entry_point: Some(fs),
                    compilation_options: Default::default(),
                    targets: &[Some(wgpu::ColorTargetState {
                        format,
                        blend: Some(wgpu::BlendState::ALPHA_BLENDING),
                        write_mask: wgpu::ColorWrites::ALL,
                    })],
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let triangles = wgpu::PrimitiveTopology::TriangleList;
        Self {
            circles: make(
                "circles",
                &shapes,
                "vs_circle",
                "fs_circle",
                CircleInstance::layout(),
                triangles,
            ),
            polygons: make(
                "polygons",
                &shapes,
                "vs_polygon",
                "fs_polygon",
                PolygonInstance::layout(),
                triangles,
            ),
            lines: make(
                "lines",
                &lines,
                "vs_line",
                "fs_line",
                LineVertex::layout(),
                wgpu::PrimitiveTopology::LineList,
            ),
            camera_layout,
        }
    }
}
