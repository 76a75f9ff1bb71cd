#define_import_path pelt::hot_spot

// The hot spot's lift of one layer's hair (prt.wgsl `hot_spot`): what the hair gets unshadowed
// over what the transfer leaves it, taken as the mean radiance `top` of the top layer (whose
// hair nothing shadows) over the layer's mean radiance `here`; at least 1. Shared by the
// fragments (level 0's layers, per fragment) and the rotation pass (the LOD composites' members,
// per vertex).
fn hot_spot_ratio(top: vec3<f32>, here: vec3<f32>) -> vec3<f32> {
    let lit = max(top, vec3<f32>(0.0));
    return max(lit / max(here, max(HOT_SPOT_FLOOR * lit, vec3<f32>(1e-6))), vec3<f32>(1.0));
}

// The top layer's mean radiance over a depth's is taken at most 1 / HOT_SPOT_FLOOR: deep in the
// fur, where the transfer holds little light, its small values are the least exact.
const HOT_SPOT_FLOOR: f32 = 0.05;

// A gain (a weighted mean of `hot_spot_ratio`s, in [1, 1 / HOT_SPOT_FLOOR]) in two words: its
// RGB as 16-bit fixed point over that range (steps of 3e-4; f16 packing needs a capability that
// not every backend has).
fn pack_gain(gain: vec3<f32>) -> vec2<u32> {
    let unit = (gain - 1.0) / (1.0 / HOT_SPOT_FLOOR - 1.0);
    return vec2<u32>(pack2x16unorm(unit.rg), pack2x16unorm(vec2<f32>(unit.b, 0.0)));
}

fn unpack_gain(packed: vec2<u32>) -> vec3<f32> {
    let unit = vec3<f32>(unpack2x16unorm(packed.x), unpack2x16unorm(packed.y).x);
    return 1.0 + unit * (1.0 / HOT_SPOT_FLOOR - 1.0);
}
