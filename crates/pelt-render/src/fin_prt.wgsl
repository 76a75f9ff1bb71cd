#define_import_path pelt::fin_prt

#import pelt::common::fin_texel
#import pelt::prt::{mean_radiance, hot_spot}
#import pelt::light_model::{FinIn, FinCorner}

// Fins under PRT lighting: the fin texture has no transfer of its own (prt-shell-fur §4 leaves
// fins to future work), so a fin row takes the mean transfer of the hair in the shell layers at
// its height, lit by its two ends' rotated lighting.

struct FinOut {
    @builtin(position) clip: vec4<f32>,
    // Fin texture uv; the weight of the second end; the hot spot (`hot_spot`).
    @location(0) uv_along_hot: vec4<f32>,
    // Vertex color; opacity.
    @location(1) color_opacity: vec4<f32>,
    // The surface vertices at the edge's ends.
    @location(2) @interpolate(flat) ends: vec2<u32>,
    // The hair's density (`FinCorner`).
    @location(3) density: f32,
};

fn fin_vertex(v: FinIn, c: FinCorner) -> FinOut {
    return FinOut(c.clip, vec4<f32>(v.uv, v.along, hot_spot(c.position)),
                  vec4<f32>(v.color.rgb, c.opacity), v.ends, c.density);
}

// Premultiplied: texel × vertex color × opacity, lit per fragment.
fn fin_fragment(f: FinOut) -> vec4<f32> {
    let uv = f.uv_along_hot.xy;
    let texel = fin_texel(uv, f.density);
    let opacity = f.color_opacity.w;
    let albedo = texel.rgb * f.color_opacity.rgb * opacity;
    let ids = vec3<u32>(f.ends, f.ends.x);
    let w = vec3<f32>(1.0 - f.uv_along_hot.z, f.uv_along_hot.z, 0.0);
    let lit = mean_radiance(ids, w, 1.0 - uv.y, f.uv_along_hot.w);
    return vec4<f32>(albedo * lit, texel.a * opacity);
}
