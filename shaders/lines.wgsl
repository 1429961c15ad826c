// Debug lines (contacts, normals, bounding boxes, the broad-phase tree, centres of mass, the
// metre grid): a line list in world coordinates, one colour per vertex, one draw call.

struct Camera {
    center: vec2<f32>,
    clip_scale: vec2<f32>,
    pixels_per_metre: f32,
    _pad0: f32,
    _pad1: f32,
    _pad2: f32,
};

@group(0) @binding(0) var<uniform> camera: Camera;

struct LineVertex {
    @location(0) position: vec2<f32>,
    @location(1) color: vec4<f32>,
};

struct LineVarying {
    @builtin(position) clip: vec4<f32>,
    @location(0) color: vec4<f32>,
};

@vertex
fn vs_line(vertex: LineVertex) -> LineVarying {
    var out: LineVarying;
    out.clip = vec4<f32>((vertex.position - camera.center) * camera.clip_scale, 0.0, 1.0);
    out.color = vertex.color;
    return out;
}

@fragment
fn fs_line(in: LineVarying) -> @location(0) vec4<f32> {
    return in.color;
}
