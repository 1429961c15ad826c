// Bodies as instanced quads shaded by signed distance: one instance per body, one draw call
// per shape kind. The vertex stage places a quad around the shape (in the body's frame, a
// couple of pixels larger than the shape, for the anti-aliased edge); the fragment stage
// computes the distance from the pixel to the shape's boundary in pixels and turns it into
// coverage (alpha), an outline, and for circles a line that shows the orientation.

struct Camera {
    // The world point at the centre of the viewport (m).
    center: vec2<f32>,
    // Clip-space units per metre on x and y.
    clip_scale: vec2<f32>,
    // Pixels per metre: converts distances in metres to pixels for anti-aliasing.
    pixels_per_metre: f32,
    _pad0: f32,
    _pad1: f32,
    _pad2: f32,
};

@group(0) @binding(0) var<uniform> camera: Camera;

// Pixels of the darker outline drawn inside each shape's edge.
const OUTLINE_PX: f32 = 1.25;
// Pixels the quad reaches beyond the shape, so the soft edge is not cut off.
const MARGIN_PX: f32 = 2.0;

// The six corners (two triangles) of the unit quad [-1, 1]².
fn quad_corner(index: u32) -> vec2<f32> {
    var corners = array<vec2<f32>, 6>(
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, -1.0), vec2<f32>(1.0, 1.0),
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, 1.0), vec2<f32>(-1.0, 1.0),
    );
    return corners[index];
}

// Rotates v by the rotation (cos, sin).
fn rotate(q: vec2<f32>, v: vec2<f32>) -> vec2<f32> {
    return vec2<f32>(q.x * v.x - q.y * v.y, q.y * v.x + q.x * v.y);
}

fn to_clip(world: vec2<f32>) -> vec4<f32> {
    return vec4<f32>((world - camera.center) * camera.clip_scale, 0.0, 1.0);
}

// Colour from the signed distance to the edge `d` (pixels, negative inside) and the distance
// to a marker line `line` (pixels; a large value for none).
fn shade(d: f32, line: f32, fill: vec4<f32>) -> vec4<f32> {
    let edge = fill.rgb * 0.55;
    // Inside the outline band (and on the marker line) the colour darkens.
    let in_outline = clamp(d + OUTLINE_PX + 0.5, 0.0, 1.0);
    let on_line = 1.0 - clamp(line - 0.6, 0.0, 1.0);
    let rgb = mix(fill.rgb, edge, max(in_outline, on_line));
    // Coverage: a one-pixel ramp centred on the edge.
    let alpha = clamp(0.5 - d, 0.0, 1.0) * fill.a;
    return vec4<f32>(rgb, alpha);
}

// ---- circles ----

struct CircleInstance {
    @location(0) center: vec2<f32>,
    @location(1) rotation: vec2<f32>,
    @location(2) color: vec4<f32>,
    @location(3) radius: f32,
};

struct CircleVarying {
    @builtin(position) clip: vec4<f32>,
    // The fragment's position in the body's frame (m).
    @location(0) local: vec2<f32>,
    @location(1) color: vec4<f32>,
    @location(2) @interpolate(flat) radius: f32,
};

@vertex
fn vs_circle(@builtin(vertex_index) vertex: u32, body: CircleInstance) -> CircleVarying {
    let half = body.radius + MARGIN_PX / camera.pixels_per_metre;
    let local = quad_corner(vertex) * half;
    var out: CircleVarying;
    out.clip = to_clip(body.center + rotate(body.rotation, local));
    out.local = local;
    out.color = body.color;
    out.radius = body.radius;
    return out;
}

@fragment
fn fs_circle(in: CircleVarying) -> @location(0) vec4<f32> {
    let px = camera.pixels_per_metre;
    let d = (length(in.local) - in.radius) * px;
    // The orientation line: the segment from the centre to the edge along the body's x axis.
    let t = clamp(in.local.x, 0.0, in.radius);
    let line = length(in.local - vec2<f32>(t, 0.0)) * px;
    return shade(d, line, in.color);
}

// ---- convex polygons, up to 8 vertices ----

struct PolygonInstance {
    @location(0) center: vec2<f32>,
    @location(1) rotation: vec2<f32>,
    @location(2) color: vec4<f32>,
    // Vertices in the body's frame, two per vec4: (v0, v1), (v2, v3), (v4, v5), (v6, v7).
    @location(3) v01: vec4<f32>,
    @location(4) v23: vec4<f32>,
    @location(5) v45: vec4<f32>,
    @location(6) v67: vec4<f32>,
    // The vertices' bounding box in the body's frame (min x, min y, max x, max y): the quad.
    @location(7) bounds: vec4<f32>,
    @location(8) count: u32,
    // Rounding radius (m); a capsule is two vertices with a radius.
    @location(9) radius: f32,
};

struct PolygonVarying {
    @builtin(position) clip: vec4<f32>,
    @location(0) local: vec2<f32>,
    @location(1) color: vec4<f32>,
    @location(2) @interpolate(flat) v01: vec4<f32>,
    @location(3) @interpolate(flat) v23: vec4<f32>,
    @location(4) @interpolate(flat) v45: vec4<f32>,
    @location(5) @interpolate(flat) v67: vec4<f32>,
    @location(6) @interpolate(flat) count: u32,
    @location(7) @interpolate(flat) radius: f32,
};

@vertex
fn vs_polygon(@builtin(vertex_index) vertex: u32, body: PolygonInstance) -> PolygonVarying {
    let margin = MARGIN_PX / camera.pixels_per_metre;
    let lo = body.bounds.xy - vec2<f32>(margin);
    let hi = body.bounds.zw + vec2<f32>(margin);
    let local = mix(lo, hi, quad_corner(vertex) * 0.5 + vec2<f32>(0.5));
    var out: PolygonVarying;
    out.clip = to_clip(body.center + rotate(body.rotation, local));
    out.local = local;
    out.color = body.color;
    out.v01 = body.v01;
    out.v23 = body.v23;
    out.v45 = body.v45;
    out.v67 = body.v67;
    out.count = body.count;
    out.radius = body.radius;
    return out;
}

// Signed distance from p to a convex counter-clockwise polygon: inside, the largest signed
// distance to an edge's line (exact for a convex shape); outside, the distance to the nearest
// edge segment (exact at the corners too). Two vertices are a segment, which has no inside.
fn sd_convex(p: vec2<f32>, vertices: array<vec2<f32>, 8>, count: u32) -> f32 {
    // A function-local copy, so the loop may index it with a runtime index.
    var v = vertices;
    var inside = -1.0e30;
    var outside = 1.0e30;
    for (var i = 0u; i < count; i = i + 1u) {
        let a = v[i];
        let b = v[(i + 1u) % count];
        let e = b - a;
        let n = normalize(vec2<f32>(e.y, -e.x));
        inside = max(inside, dot(n, p - a));
        let h = clamp(dot(p - a, e) / dot(e, e), 0.0, 1.0);
        outside = min(outside, length(p - a - e * h));
    }
    if (inside > 0.0 || count < 3u) {
        return outside;
    }
    return inside;
}

@fragment
fn fs_polygon(in: PolygonVarying) -> @location(0) vec4<f32> {
    let v = array<vec2<f32>, 8>(
        in.v01.xy, in.v01.zw, in.v23.xy, in.v23.zw,
        in.v45.xy, in.v45.zw, in.v67.xy, in.v67.zw,
    );
    // A rounded shape is the polygon grown by its radius: its distance less the radius.
    let d = (sd_convex(in.local, v, min(in.count, 8u)) - in.radius) * camera.pixels_per_metre;
    return shade(d, 1.0e6, in.color);
}
