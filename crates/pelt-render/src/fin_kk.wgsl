#define_import_path pelt::fin_kk

#import pelt::common::{frame, view_vector, unit_or, fin_texel, body_shadow}
#import pelt::lighting::hair_terms
#import pelt::light_model::{FinIn, FinCorner}

// Fins under Kajiya-Kay lighting: the fin texture has no tangent map, its hair runs along the
// growth direction. A fin is a few pixels across, so it is lit at its corners and the lighting
// interpolated (Lengyel et al. 2001, §2.4, also computes u = T·L and v = T·H per vertex, through
// the texture matrix): the fragment is left a texture read and two multiply-adds, which a CPU
// adapter feels on tens of thousands of fins.

struct FinOut {
    @builtin(position) clip: vec4<f32>,
    // Vertex color × opacity × the lighting's scale; fin texture u.
    @location(0) scale_u: vec4<f32>,
    // Opacity × the highlight's multiple of the light color; fin texture v; opacity. Two
    // locations, not three: a CPU adapter sets up every location of every fin triangle on one
    // thread (a fifth of the fins' time on llvmpipe).
    @location(1) shine_v_opacity: vec3<f32>,
};

fn fin_vertex(v: FinIn, c: FinCorner) -> FinOut {
    let n = unit_or(c.normal, vec3<f32>(0.0, 0.0, 1.0));
    let t = unit_or(c.growth, n);
    let k = hair_terms(t, n, view_vector(c.position), 1.0 - v.uv.y, v.length, c.wrap,
                       body_shadow(c.position, n));
    return FinOut(c.clip, vec4<f32>(v.color.rgb * c.opacity * k.scale, v.uv.x),
                  vec3<f32>(c.opacity * k.shine, v.uv.y, c.opacity));
}

// Premultiplied: texel × vertex color × opacity, lit.
fn fin_fragment(f: FinOut) -> vec4<f32> {
    let texel = fin_texel(vec2<f32>(f.scale_u.w, f.shine_v_opacity.y));
    let add = frame.light_color.rgb * f.shine_v_opacity.x;
    return vec4<f32>(texel.rgb * f.scale_u.rgb + texel.a * add, texel.a * f.shine_v_opacity.z);
}
