// A single-float frame copied into a caller's texture (`resolve.rs`): one triangle over the
// whole frame, each pixel read as it is; the target's format encodes it.

@group(0) @binding(0) var frame: texture_2d<f32>;

// One triangle over the whole frame.
@vertex
fn vs_main(@builtin(vertex_index) index: u32) -> @builtin(position) vec4<f32> {
    let corner = vec2<f32>(f32((index << 1u) & 2u), f32(index & 2u));
    return vec4<f32>(corner * 2.0 - 1.0, 0.0, 1.0);
}

@fragment
fn fs_main(@builtin(position) pixel: vec4<f32>) -> @location(0) vec4<f32> {
    return textureLoad(frame, vec2<i32>(pixel.xy), 0);
}
