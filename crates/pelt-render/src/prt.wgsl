#define_import_path pelt::prt

#import pelt::common::{frame, tile_sampler, shell_texture, shared_path, view_vector, HEIGHT_NODES}
#import pelt::hot_spot::{hot_spot_ratio, unpack_gain}

// Precomputed radiance transfer (prt-shell-fur §2.4): the lighting, already rotated into each
// surface vertex's tile frame by the compute pass (`prt_rotate.wgsl`), dotted per fragment with
// the transfer coefficients of the fragment's texel and layer. The transfer textures hold
// coefficient k in texture k / 4, channel k % 4, all textures in one array (`frame.prt.z`
// layers each). Output is albedo × the dot product (the 1/π is folded into the lighting).

@group(1) @binding(0) var transfer_texture: texture_2d_array<f32>;
// Per surface vertex, n² rotated coefficients (RGB).
@group(1) @binding(1) var<storage, read> rotated: array<vec4<f32>>;
// Per level-0 layer, the opacity-weighted mean of each coefficient: the fins' transfer and the
// hot spot's measure of a layer's; then the LOD composites' heights (`shown_heights`) and the
// rows the rotation pass reads (`transfer::composite_members`).
@group(1) @binding(2) var<storage, read> layer_means: array<f32>;
// Per surface vertex and LOD composite, the hot spot's gain (`prt_rotate.wgsl`, `pack_gain`).
@group(1) @binding(4) var<storage, read> composite_gains: array<vec2<u32>>;

// The rotated lighting at a point between surface vertices `ids` with weights `w`.
fn light_at(ids: vec3<u32>, w: vec3<f32>, k: u32) -> vec3<f32> {
    let n = frame.prt.x;
    return (w.x * rotated[ids.x * n + k] + w.y * rotated[ids.y * n + k]
        + w.z * rotated[ids.z * n + k]).rgb;
}

// Σ_k L'_k t_k with the transfer sampled at `uv` in layer `layer` of every transfer texture;
// `alpha` is the shell texel's opacity sampled alike, which the premultiplied transfer divides
// out. Raised by the hot spot `hot` (`hot_spot`): a level-0 layer by its own mean transfer,
// whose mean radiances (`hot_spot_factor`) are summed in the same loop, so the lighting is read
// once; an LOD composite by its members' factors weighed per vertex (`composite_gain`).
fn transfer_radiance(ids: vec3<u32>, w: vec3<f32>, uv: vec2<f32>, layer: u32, grad: vec4<f32>,
                     alpha: f32, hot: f32) -> vec3<f32> {
    let n = frame.prt.x;
    let composite = layer >= frame.prt.w;
    let clears = hot > 0.0 && !composite;
    var sum = vec3<f32>(0.0);
    var m = MeanRadiances(vec3<f32>(0.0), vec3<f32>(0.0));
    for (var t = 0u; t < frame.prt.y; t++) {
        let c = textureSampleGrad(transfer_texture, tile_sampler, uv, t * frame.prt.z + layer,
                                  grad.xy, grad.zw);
        for (var ch = 0u; ch < 4u && 4u * t + ch < n; ch++) {
            let k = 4u * t + ch;
            let l = light_at(ids, w, k);
            sum += l * c[ch];
            if (clears) {
                m.here += l * layer_means[layer * n + k];
                m.top += l * top_transfer(k);
            }
        }
    }
    // A band-limited light rings slightly negative past the terminator.
    let radiance = max(sum / max(alpha, 1e-4), vec3<f32>(0.0));
    if (clears) {
        return radiance * hot_spot_factor(m, hot);
    }
    if (hot > 0.0) {
        return radiance * (1.0 + hot * (composite_gain(ids, w, layer - frame.prt.w) - 1.0));
    }
    return radiance;
}

// The hot spot's gain of LOD composite `j` (past level 0) between surface vertices `ids` with
// weights `w`: what all shells' own factors make of its members' light over that light.
fn composite_gain(ids: vec3<u32>, w: vec3<f32>, j: u32) -> vec3<f32> {
    let count = frame.prt.z - frame.prt.w;
    var gain = vec3<f32>(0.0);
    for (var c = 0u; c < 3u; c++) {
        gain += w[c] * unpack_gain(composite_gains[ids[c] * count + j]);
    }
    return gain;
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

// Σ_k L'_k t̄_k with the hair's mean transfer at `height`, and at the top layer where the hot spot
// `hot` needs it (else 0: the fins' and strands' frames away from it skip the reads).
struct MeanRadiances {
    here: vec3<f32>,
    top: vec3<f32>,
};

fn mean_radiances(ids: vec3<u32>, w: vec3<f32>, height: f32, hot: f32) -> MeanRadiances {
    var m = MeanRadiances(vec3<f32>(0.0), vec3<f32>(0.0));
    for (var k = 0u; k < frame.prt.x; k++) {
        let l = light_at(ids, w, k);
        m.here += l * mean_transfer(k, height);
        if (hot > 0.0) {
            m.top += l * top_transfer(k);
        }
    }
    return m;
}

// The mean and mean square of the level-0 heights (in layers) of the hair that array layer
// `layer` shows read at mip level `mip`: a level-0 layer its own `height`, an LOD composite its
// members' weighed as all shells weigh them there (`shown_heights.rs`; after level 0's rows,
// per mip level, per composite).
fn shown_heights(layer: u32, height: u32, mip: f32) -> vec2<f32> {
    if (layer < frame.prt.w) {
        let h = f32(height);
        return vec2<f32>(h, h * h);
    }
    let composites = frame.prt.z - frame.prt.w;
    let level = min(u32(max(mip, 0.0)), textureNumLevels(shell_texture) - 1u);
    let at = frame.prt.w * frame.prt.x + 2u * (level * composites + layer - frame.prt.w);
    return vec2<f32>(layer_means[at], layer_means[at + 1u]);
}

// The mean transfer coefficient k of the top layer's hair.
fn top_transfer(k: u32) -> f32 {
    return layer_means[(frame.prt.w - 1u) * frame.prt.x + k];
}

// The hot spot (Hapke's shadow hiding): where the directional light comes from the eye, the path
// it takes through the fur is the view ray's own, which the composite shows clear, so the hair
// the eye sees is lit as if unshadowed; the transfer shadows it all the same (light from the eye
// left PRT's fronts at 0.67 of the reference). How much of the lighting clears at `position`:
// the directional light's share of it (`frame.light_direction.w`,
// `LightingFrame::hot_spot_share`) × `shared_path`.
// `shared_path` is taken from HOT_SPOT_MIN up, rescaled to stay continuous: more than 60° from
// the light nothing clears and the hot spot costs nothing.
fn hot_spot(position: vec3<f32>) -> f32 {
    let clear = shared_path(frame.light_direction.xyz, view_vector(position));
    return frame.light_direction.w * max(clear - HOT_SPOT_MIN, 0.0) / (1.0 - HOT_SPOT_MIN);
}

// See `hot_spot`: e^(−60° / HOT_SPOT_WIDTH) ≈ 0.05.
const HOT_SPOT_MIN: f32 = 0.05;

// The factor the hot spot `hot` raises radiance at a height by: unshadowed over shadowed,
// `hot_spot_ratio` of the hair's mean radiances at the top layer and at the height.
fn hot_spot_factor(m: MeanRadiances, hot: f32) -> vec3<f32> {
    return 1.0 + hot * (hot_spot_ratio(m.top, m.here) - 1.0);
}

// Σ_k L'_k t̄_k with the hair's mean transfer at `height`, raised by the hot spot `hot`: the
// light of the fins and the guard strands, which read no texel's transfer.
fn mean_radiance(ids: vec3<u32>, w: vec3<f32>, height: f32, hot: f32) -> vec3<f32> {
    return raised(mean_radiances(ids, w, height, hot), hot);
}

// The mean radiance `m.here`, clamped at 0 (a band-limited light rings past the terminator),
// raised by the hot spot `hot`.
fn raised(m: MeanRadiances, hot: f32) -> vec3<f32> {
    return max(m.here, vec3<f32>(0.0)) * hot_spot_factor(m, hot);
}

// `mean_radiance` at each of the HEIGHT_NODES heights the marched composites are lit at, the
// lighting read once for all.
fn node_radiances(ids: vec3<u32>, w: vec3<f32>, hot: f32) -> array<vec3<f32>, HEIGHT_NODES> {
    var here: array<vec3<f32>, HEIGHT_NODES>;
    var top = vec3<f32>(0.0);
    let spacing = 1.0 / f32(HEIGHT_NODES - 1u);
    for (var k = 0u; k < frame.prt.x; k++) {
        let l = light_at(ids, w, k);
        for (var j = 0u; j < HEIGHT_NODES; j++) {
            here[j] += l * mean_transfer(k, f32(j) * spacing);
        }
        if (hot > 0.0) {
            top += l * top_transfer(k);
        }
    }
    for (var j = 0u; j < HEIGHT_NODES; j++) {
        here[j] = raised(MeanRadiances(here[j], top), hot);
    }
    return here;
}
