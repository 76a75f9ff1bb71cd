#define_import_path pelt::surface_kk

#import pelt::common::{
    frame, tangent_texture, tile_sampler, Layers, skin_layers, shading_height,
    level_shading_height, HairLight, Shown,
    clip_position, view_vector, unit_or, surface_curvature, body_shadow, screen_steps,
    curvature_of_steps, screen_spread,
}
#import pelt::lighting::{banks_strengths, hair_parts, shade, shade_skin, terminator_wrap}
#import pelt::surface::{SurfaceData, lift, Texels, layer_texels, blended, MarchFrame}

// The skin and shells under Kajiya-Kay lighting (Lengyel et al. 2001, §2.4): vertices come from
// the vertex buffers, the tangent map gives the hair direction per texel.

struct SurfaceIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) dpdu: vec3<f32>,
    @location(3) dpdv: vec3<f32>,
    @location(4) uv: vec2<f32>,
    @location(5) comb: vec3<f32>,
    @location(6) color: vec4<f32>,
    @location(7) length: f32,
    @location(8) border: vec2<f32>,
};

// What the fragment reads, unpacked from `SurfaceVarying`.
struct SurfaceOut {
    position: vec3<f32>,
    normal: vec3<f32>,
    dpdu: vec3<f32>,
    dpdv: vec3<f32>,
    up: vec3<f32>,
    uv: vec2<f32>,
    color: vec4<f32>,
    length: f32,
    // Array layers of the level drawn and the coarser one, level-0 height (see `Layers`).
    layer: u32,
    coarse: u32,
    height: u32,
    // Tile units to the open border (`SurfaceVertex::border`).
    border: vec2<f32>,
};

// `SurfaceOut` as it crosses from vertex to fragment, packed into few vec4s: a CPU adapter sets
// up and interpolates every output location of every triangle, whatever its width.
struct SurfaceVarying {
    @builtin(position) clip: vec4<f32>,
    @location(0) position_length: vec4<f32>,
    @location(1) normal_u: vec4<f32>,
    @location(2) dpdu_v: vec4<f32>,
    // dP/dv and the border distances, dP/dheight: packed with them.
    @location(3) dpdv_border: vec4<f32>,
    @location(4) up_border: vec4<f32>,
    @location(5) color: vec4<f32>,
    // Layer drawn, coarser layer, height.
    @location(6) @interpolate(flat) layers: vec3<u32>,
};

fn surface_fragment(v: SurfaceVarying) -> SurfaceOut {
    return SurfaceOut(v.position_length.xyz, v.normal_u.xyz, v.dpdu_v.xyz, v.dpdv_border.xyz,
                      v.up_border.xyz, vec2<f32>(v.normal_u.w, v.dpdu_v.w), v.color,
                      v.position_length.w, v.layers.x, v.layers.y, v.layers.z,
                      vec2<f32>(v.dpdv_border.w, v.up_border.w));
}

// The vertex lifted to level-0 height `stand` (in layers), with its painted length (`painted`)
// or the length multiplier 1.
fn surface_vertex(v: SurfaceIn, layers: Layers, stand: f32, painted: bool) -> SurfaceVarying {
    let d = SurfaceData(v.position, v.normal, v.dpdu, v.dpdv, v.uv, v.comb, v.color, v.length);
    let lifted = lift(d, stand, select(1.0, v.length, painted));
    return SurfaceVarying(lifted.clip, vec4<f32>(lifted.position, v.length),
                          vec4<f32>(v.normal, v.uv.x), vec4<f32>(v.dpdu, v.uv.y),
                          vec4<f32>(v.dpdv, v.border.x), vec4<f32>(lifted.up, v.border.y), v.color,
                          vec3<u32>(layers.fine, layers.coarse, layers.height));
}

// The skin needs only its position (for the view), normal, tile UV, color and painted length
// (its texel layers are the frame's).
struct SkinVarying {
    @builtin(position) clip: vec4<f32>,
    @location(0) normal_u: vec4<f32>,
    @location(1) position_v: vec4<f32>,
    @location(2) color_length: vec4<f32>,
};

// The skin stays where the mesh is (height 0).
fn skin_vertex(v: SurfaceIn) -> SkinVarying {
    return SkinVarying(clip_position(v.position), vec4<f32>(v.normal, v.uv.x),
                       vec4<f32>(v.position, v.uv.y), vec4<f32>(v.color.rgb, v.length));
}

// Layer 0 of the level drawn (cross-faded into the coarser level's under LOD) × vertex color,
// lit as the skin under the fur painted over it (bald skin: Lambertian, undarkened).
fn skin_fragment(s: SkinVarying) -> vec3<f32> {
    let layers = skin_layers();
    let uv = vec2<f32>(s.normal_u.w, s.position_v.w);
    let texel = blended(layer_texels(uv, layers.fine, layers.coarse));
    let n = unit_or(s.normal_u.xyz, vec3<f32>(0.0, 0.0, 1.0));
    let hair_length = s.color_length.w;
    let wrap = terminator_wrap(surface_curvature(n, s.position_v.xyz), frame.fur.x * hair_length);
    let shadow = body_shadow(s.position_v.xyz, n);
    return shade_skin(texel.rgb * s.color_length.rgb, n, view_vector(s.position_v.xyz), hair_length,
                      wrap, shadow);
}

// How the fragment's triangle grows with height, from the steps of its varyings.
fn surface_spread(s: SurfaceOut, stand: f32) -> vec2<f32> {
    return screen_spread(s.position, s.up, stand);
}

// The terminator band's width under the shell's hair (its painted length × the fur depth).
fn surface_wrap(s: SurfaceOut) -> f32 {
    let n = unit_or(s.normal, vec3<f32>(0.0, 0.0, 1.0));
    return terminator_wrap(surface_curvature(n, s.position), frame.fur.x * s.length);
}

// A shell's cross-faded texel × vertex color, lit as hair (the model is linear in the texel, so
// one shading of the blend is the blend of two; the skin has `skin_fragment`); premultiplied,
// opacity × texel alpha. `grad` is unused here (the tangent map has one level).
fn shade_surface(s: SurfaceOut, texels: Texels, opacity: f32, grad: vec4<f32>,
                 wrap: f32) -> vec4<f32> {
    let texel = blended(texels);
    let n = unit_or(s.normal, vec3<f32>(0.0, 0.0, 1.0));
    // Lit, and its hair direction read, at its group's middle: the tangent at the group's top
    // (tips, on short fur) lit the LOD up to 15% brighter than the all-shells image on the patch.
    let lit = shading_height(Layers(s.height, s.layer, s.coarse));
    let t = tangent_between(s.uv, lit, s.dpdu, s.dpdv, s.up, n);
    let albedo = texel.rgb * s.color.rgb * opacity;
    let height = lit * frame.fur.y;
    return shade(albedo, texel.a * opacity, t, n, view_vector(s.position), height, s.length,
                 wrap, body_shadow(s.position, n));
}

// The hair tangent of the tangent map carried from the tile frame (x along u, y along v, z up)
// to the surface. The map has one level, so sampling it at level 0 costs no derivatives.
fn hair_tangent(uv: vec2<f32>, layer: u32, dpdu: vec3<f32>, dpdv: vec3<f32>, up: vec3<f32>,
                n: vec3<f32>) -> vec3<f32> {
    let d = textureSampleLevel(tangent_texture, tile_sampler, uv, layer, 0.0).xyz * 2.0 - 1.0;
    return unit_or(d.x * dpdu + d.y * dpdv + d.z * up, n);
}

// The hair tangent at the fractional layer `at`, mixed between the two layers about it so that it
// moves smoothly with the LOD cross-fade (a whole layer, without LOD, costs one read).
fn tangent_between(uv: vec2<f32>, at: f32, dpdu: vec3<f32>, dpdv: vec3<f32>, up: vec3<f32>,
                   n: vec3<f32>) -> vec3<f32> {
    let below = floor(at);
    let a = hair_tangent(uv, u32(below), dpdu, dpdv, up, n);
    if (at == below) {
        return a;
    }
    let b = hair_tangent(uv, u32(below) + 1u, dpdu, dpdv, up, n);
    return unit_or(mix(a, b, at - below), n);
}

// The hull fragment's point, tile frame and curvature for the marched shells (`marched.wgsl`).
fn march_frame(s: SurfaceOut) -> MarchFrame {
    return MarchFrame(s.position, s.normal, s.dpdu, s.dpdv, s.up,
                      screen_steps(s.normal, s.position), s.border,
                      vec4<f32>(dpdx(s.border), dpdy(s.border)),
                      surface_spread(s, f32(s.height) * frame.fur.y));
}

// The hair lighting at the marched layer `layers` read at `uv`, before Banks darkening (at the
// top of the fur it is none), which the march applies layer by layer (`march_banks`); the
// body's shadow is read at the composite's mean height (`heights.mean`).
fn march_light(s: SurfaceOut, f: MarchFrame, uv: vec2<f32>, layers: Layers, alpha: f32,
               grad: vec4<f32>, heights: Shown) -> HairLight {
    let n = unit_or(f.normal, vec3<f32>(0.0, 0.0, 1.0));
    let t = hair_tangent(uv, layers.height, f.dpdu, f.dpdv, f.up, n);
    let wrap = terminator_wrap(curvature_of_steps(f.steps), frame.fur.x * s.length);
    // Shadowed where the composite stands: its mean height, below the hull.
    let below = f.up * (f32(s.height) * frame.fur.y - heights.mean);
    let p = hair_parts(t, n, view_vector(f.position), wrap, body_shadow(f.position - below, n));
    return HairLight(p.ambient, p.direct, frame.light_color.rgb * p.shine);
}

// The virtual planes' lighting: the marched layer's, at the height where their composite passes
// half opacity (`planes.wgsl`).
fn plane_light(s: SurfaceOut, f: MarchFrame, uv: vec2<f32>, layers: Layers, grad: vec4<f32>,
               heights: Shown) -> HairLight {
    return march_light(s, f, uv, layers, 1.0, grad, heights);
}

// The heights the march composites a layer of `layers` at (`march.wgsl` `composite`), that of the
// level drawn or (`coarse`) of its coarser twin, at any mip level: where it is lit
// (`level_shading_height`), its hair spread evenly over the group's 2^k level-0 layers (one
// without LOD, whose level is 0).
fn march_heights(layers: Layers, coarse: bool, mip: f32) -> vec2<f32> {
    let group = select(frame.lod.z, 2u * frame.lod.z, coarse);
    let h = level_shading_height(layers.height, group);
    let g = f32(group);
    return vec2<f32>(h, h * h + (g * g - 1.0) / 12.0);
}

// The Banks strengths the march darkens its layers by: x the ambient's, y the direct light's,
// under the hull's painted length.
fn march_banks(s: SurfaceOut, f: MarchFrame) -> vec2<f32> {
    let n = unit_or(f.normal, vec3<f32>(0.0, 0.0, 1.0));
    return banks_strengths(n, frame.light_direction.xyz, view_vector(f.position), s.length);
}
