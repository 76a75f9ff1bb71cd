// The frame's starting depth from another renderer's depth of the same view (`occluders.rs`):
// each pixel's surface pushed back along its view ray by the bias, so the fur behind another
// object fails the depth test, and the fur's own surfaces in that picture (the skin, shells
// drawn opaque) do not hide it.

struct Occluders {
    // Object space to wgpu clip space, and back.
    view_proj: mat4x4<f32>,
    inverse_view_proj: mat4x4<f32>,
    // The eye in object space: w = 1 a position, w = 0 the direction toward the viewer.
    eye: vec4<f32>,
    // x: the bias (object units); y, z: the frame's width and height in pixels.
    bias_size: vec4<f32>,
}

@group(0) @binding(0) var<uniform> occluders: Occluders;
@group(0) @binding(1) var occluder_depth: texture_2d<f32>;

@fragment
fn fs_main(@builtin(position) pixel: vec4<f32>) -> @builtin(frag_depth) f32 {
    let depth = textureLoad(occluder_depth, vec2<i32>(pixel.xy), 0).r;
    if (depth >= 1.0) {
        return 1.0;  // nothing there
    }
    let size = occluders.bias_size.yz;
    let ndc = vec2<f32>(pixel.x / size.x * 2.0 - 1.0, 1.0 - pixel.y / size.y * 2.0);
    let h = occluders.inverse_view_proj * vec4<f32>(ndc, depth, 1.0);
    let surface = h.xyz / h.w;
    let eye = occluders.eye;
    let away = select(-eye.xyz, surface - eye.xyz, eye.w != 0.0);
    let length_away = length(away);
    if (!(length_away > 0.0)) {
        return depth;
    }
    let behind = surface + away / length_away * occluders.bias_size.x;
    let clip = occluders.view_proj * vec4<f32>(behind, 1.0);
    return clamp(clip.z / clip.w, depth, 1.0);
}
