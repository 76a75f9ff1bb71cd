// A single-float frame copied into a caller's texture (`resolve.rs`), each pixel read as it is
// over the full-frame triangle (`full_frame.wgsl`); the target's format encodes it.

@group(0) @binding(0) var frame: texture_2d<f32>;

@fragment
fn fs_main(@builtin(position) pixel: vec4<f32>) -> @location(0) vec4<f32> {
    return textureLoad(frame, vec2<i32>(pixel.xy), 0);
}
