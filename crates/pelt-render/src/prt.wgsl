#define_import_path pelt::prt

#import pelt::common::{frame, tile_sampler}

// Precomputed radiance transfer (prt-shell-fur §2.4): the lighting, already rotated into each
// surface vertex's tile frame by the compute pass (`prt_rotate.wgsl`), dotted per fragment with
// the transfer coefficients of the fragment's texel and layer. The transfer textures hold
// coefficient k in texture k / 4, channel k % 4, all textures in one array (`frame.prt.z`
// layers each). Output is albedo × the dot product (the 1/π is folded into the lighting).

@group(1) @binding(0) var transfer_texture: texture_2d_array<f32>;
// Per surface vertex, n² rotated coefficients (RGB).
@group(1) @binding(1) var<storage, read> rotated: array<vec4<f32>>;
// Per volume layer, the opacity-weighted mean of each coefficient: the fins' transfer.
@group(1) @binding(2) var<storage, read> layer_means: array<f32>;

// The rotated lighting at a point between surface vertices `ids` with weights `w`.
fn light_at(ids: vec3<u32>, w: vec3<f32>, k: u32) -> vec3<f32> {
    let n = frame.prt.x;
    return (w.x * rotated[ids.x * n + k] + w.y * rotated[ids.y * n + k]
        + w.z * rotated[ids.z * n + k]).rgb;
}

// Σ_k L'_k t_k with the transfer sampled at `uv` in layer `layer` of every transfer texture;
// `alpha` is the shell texel's opacity sampled alike, which the premultiplied transfer divides
// out.
fn transfer_radiance(ids: vec3<u32>, w: vec3<f32>, uv: vec2<f32>, layer: u32, grad: vec4<f32>,
                     alpha: f32) -> vec3<f32> {
    let n = frame.prt.x;
    var sum = vec3<f32>(0.0);
    for (var t = 0u; t < frame.prt.y; t++) {
        let c = textureSampleGrad(transfer_texture, tile_sampler, uv, t * frame.prt.z + layer,
                                  grad.xy, grad.zw);
        for (var ch = 0u; ch < 4u && 4u * t + ch < n; ch++) {
            sum += light_at(ids, w, 4u * t + ch) * c[ch];
        }
    }
    // A band-limited light rings slightly negative past the terminator.
    return max(sum / max(alpha, 1e-4), vec3<f32>(0.0));
}

// The hair's mean transfer coefficient k at `height` (share of the fur depth): linear between
// the layers around it.
fn mean_transfer(k: u32, height: f32) -> f32 {
    let n = frame.prt.x;
    let top = frame.prt.w - 1u;
    let at = clamp(height / frame.fur.y, 0.0, f32(top));
    let below = min(u32(at), top);
    let above = min(below + 1u, top);
    return mix(layer_means[below * n + k], layer_means[above * n + k], at - f32(below));
}

// Σ_k L'_k t̄_k with the hair's mean transfer at `height` for the fins, which have no transfer of
// their own.
fn mean_radiance(ids: vec3<u32>, w: vec3<f32>, height: f32) -> vec3<f32> {
    var sum = vec3<f32>(0.0);
    for (var k = 0u; k < frame.prt.x; k++) {
        sum += light_at(ids, w, k) * mean_transfer(k, height);
    }
    return max(sum, vec3<f32>(0.0));
}

// How much the mean radiance changes from height `start` to height `end`.
fn mean_radiance_change(ids: vec3<u32>, w: vec3<f32>, start: f32, end: f32) -> vec3<f32> {
    var sum = vec3<f32>(0.0);
    for (var k = 0u; k < frame.prt.x; k++) {
        sum += light_at(ids, w, k) * (mean_transfer(k, end) - mean_transfer(k, start));
    }
    return sum;
}
