#define_import_path pelt::fin_kk

#import pelt::common::{frame, view_vector, unit_or, fin_texel, body_shadow}
#import pelt::lighting::{half_vector, spread_hair_parts, parts_terms}
#import pelt::light_model::{FinIn, FinCorner}

// Fins under Kajiya-Kay lighting: the fin texture has no tangent map; its hair stands about the
// growth direction, spread as the tangent map's directions are (`spread_squares`). A fin is a few pixels across, so it is lit at its corners and the lighting
// interpolated (Lengyel et al. 2001, §2.4, also computes u = T·L and v = T·H per vertex, through
// the texture matrix): the fragment is left a texture read and two multiply-adds, which a CPU
// adapter feels on tens of thousands of fins.

struct FinOut {
    @builtin(position) clip: vec4<f32>,
    // Vertex color × opacity × the lighting's scale; fin texture u.
    @location(0) scale_u: vec4<f32>,
    // Opacity × the highlight's multiple of the light color; fin texture v; opacity; the hair's
    // density (`FinCorner`). Two locations, not three: a CPU adapter sets up every location of
    // every fin triangle on one thread (a fifth of the fins' time on llvmpipe).
    @location(1) shine_v_opacity_density: vec4<f32>,
};

// The mean of (d·a)² over the hair's unit directions, carried from the tile frame into object
// space by the columns `du`, `dv`, `up` (as `hair_tangent` carries one), for each of the two
// unit directions `a` (the light, the half vector) in `dirs`: E[(A d · a)²] / E[|A d|²] from the
// second moment E[d dᵀ] (`frame.fin_tangents`). The growth direction `t`'s own squares where
// there is no hair to take them from.
fn spread_squares(du: vec3<f32>, dv: vec3<f32>, up: vec3<f32>, t: vec3<f32>, light: vec3<f32>,
                  half: vec3<f32>) -> vec2<f32> {
    let m0 = frame.fin_tangents[0];
    let m1 = frame.fin_tangents[1];
    let norm = m0.x * dot(du, du) + m0.y * dot(dv, dv) + m0.z * dot(up, up)
        + 2.0 * (m0.w * dot(du, dv) + m1.x * dot(du, up) + m1.y * dot(dv, up));
    if (!(norm > 1e-20)) {
        let u = dot(t, light);
        let v = dot(t, half);
        return vec2<f32>(u * u, v * v);
    }
    let l = vec3<f32>(dot(du, light), dot(dv, light), dot(up, light));
    let h = vec3<f32>(dot(du, half), dot(dv, half), dot(up, half));
    return vec2<f32>(moment_of(l, m0, m1), moment_of(h, m0, m1)) / norm;
}

// aᵀ M a for the packed symmetric M.
fn moment_of(a: vec3<f32>, m0: vec4<f32>, m1: vec4<f32>) -> f32 {
    return m0.x * a.x * a.x + m0.y * a.y * a.y + m0.z * a.z * a.z
        + 2.0 * (m0.w * a.x * a.y + m1.x * a.x * a.z + m1.y * a.y * a.z);
}

fn fin_vertex(v: FinIn, c: FinCorner) -> FinOut {
    let n = unit_or(c.normal, vec3<f32>(0.0, 0.0, 1.0));
    let t = unit_or(c.growth, n);
    let view = view_vector(c.position);
    let up = frame.fur.x * max(v.length, 0.0) * c.growth;
    let squares = spread_squares(c.dpdu, c.dpdv, up, t, frame.light_direction.xyz,
                                 half_vector(n, view));
    let p = spread_hair_parts(t, squares, n, view, c.wrap, body_shadow(c.position, n));
    let k = parts_terms(p, n, view, 1.0 - v.uv.y, v.length);
    return FinOut(c.clip, vec4<f32>(v.color.rgb * c.opacity * k.scale, v.uv.x),
                  vec4<f32>(c.opacity * k.shine, v.uv.y, c.opacity, c.density));
}

// Premultiplied: texel × vertex color × opacity, lit.
fn fin_fragment(f: FinOut) -> vec4<f32> {
    let s = f.shine_v_opacity_density;
    let texel = fin_texel(vec2<f32>(f.scale_u.w, s.y), s.w);
    let add = frame.light_color.rgb * s.x;
    return vec4<f32>(texel.rgb * f.scale_u.rgb + texel.a * add, texel.a * s.z);
}
