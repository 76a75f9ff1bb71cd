// Smoke pass: one triangle covering the middle of the target in a flat color.

struct VertexOut {
    @builtin(position) position: vec4<f32>,
};

@vertex
fn vs_main(@builtin(vertex_index) index: u32) -> VertexOut {
    var corners = array<vec2<f32>, 3>(vec2<f32>(-0.8, -0.8), vec2<f32>(0.8, -0.8), vec2<f32>(0.0, 0.8));
    var out: VertexOut;
    out.position = vec4<f32>(corners[index], 0.0, 1.0);
    return out;
}

@fragment
fn fs_main() -> @location(0) vec4<f32> {
    // linear (204, 102, 51) / 255 in an Rgba8Unorm target
    return vec4<f32>(0.8, 0.4, 0.2, 1.0);
}
