// The vertex format and shading shared by the skin and the shells (Lengyel et al. 2001, §2.3):
// both draw the mesh textured by a layer of the shell texture; the shells lift it off the skin.

struct SurfaceIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) dpdu: vec3<f32>,
    @location(3) dpdv: vec3<f32>,
    @location(4) uv: vec2<f32>,
    @location(5) comb: vec3<f32>,
    @location(6) color: vec4<f32>,
    @location(7) length: f32,
};

struct SurfaceOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) dpdu: vec3<f32>,
    @location(3) dpdv: vec3<f32>,
    // d(position) / d(tile height): where the tile's up axis points, in object units.
    @location(4) up: vec3<f32>,
    @location(5) uv: vec2<f32>,
    @location(6) color: vec4<f32>,
    @location(7) length: f32,
    @location(8) @interpolate(flat) layer: u32,
};

// Layer `layer` sits at `layer × spacing` of the fur depth × `length` along the growth direction.
fn surface_vertex(v: SurfaceIn, layer: u32, length: f32) -> SurfaceOut {
    let up = frame.fur.x * length * growth(v.normal, v.comb);
    let p = v.position + f32(layer) * frame.fur.y * up;
    var out: SurfaceOut;
    out.clip = clip_position(p);
    out.position = p;
    out.normal = v.normal;
    out.dpdu = v.dpdu;
    out.dpdv = v.dpdv;
    out.up = up;
    out.uv = v.uv;
    out.color = v.color;
    out.length = v.length;
    out.layer = layer;
    return out;
}

// The shell texture's texel (premultiplied) at the fragment.
fn surface_texel(s: SurfaceOut) -> vec4<f32> {
    return textureSample(shell_texture, tile_sampler, s.uv, s.layer);
}

// `texel` × vertex color, lit with the hair tangent of the tangent map carried from the tile frame
// (x along u, y along v, z up) to the surface; premultiplied, opacity × texel alpha. The tangent
// map has one level, so sampling it at level 0 costs no derivatives and may follow a discard.
fn shade_surface(s: SurfaceOut, texel: vec4<f32>, opacity: f32) -> vec4<f32> {
    let packed = textureSampleLevel(tangent_texture, tile_sampler, s.uv, s.layer, 0.0).xyz;
    let d = packed * 2.0 - 1.0;
    let n = unit_or(s.normal, vec3<f32>(0.0, 0.0, 1.0));
    let t = unit_or(d.x * s.dpdu + d.y * s.dpdv + d.z * s.up, n);
    let albedo = texel.rgb * s.color.rgb * opacity;
    let height = f32(s.layer) * frame.fur.y;
    return shade(albedo, texel.a * opacity, t, n, view_vector(s.position), height);
}
