// One triangle over the whole frame: the vertex stage of the passes that work per pixel
// (`full_frame.rs`), prepended to each pass's fragment source.

@vertex
fn vs_main(@builtin(vertex_index) index: u32) -> @builtin(position) vec4<f32> {
    let corner = vec2<f32>(f32((index << 1u) & 2u), f32(index & 2u));
    return vec4<f32>(corner * 2.0 - 1.0, 0.0, 1.0);
}
