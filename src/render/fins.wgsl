// Pass (b), the fins (Lengyel et al. 2001, §2.3): one quad per mesh edge standing along the
// growth direction, faded by max(0, 2|p| - 1) with p = fin normal · view direction, so that only
// fins near the silhouette (also just over the horizon) show. Depth tested, not written. The
// lighting model's file (`fin_kk.wgsl` or `fin_prt.wgsl`) defines `shade_fin`.

struct FinIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) comb: vec3<f32>,
    @location(3) fin_normal: vec3<f32>,
    @location(4) center: vec3<f32>,
    @location(5) uv: vec2<f32>,
    @location(6) color: vec4<f32>,
    @location(7) length: f32,
    @location(8) ends: vec2<u32>,
    @location(9) along: f32,
};

struct FinOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) growth: vec3<f32>,
    @location(3) uv: vec2<f32>,
    @location(4) color: vec4<f32>,
    @location(5) fade: f32,
    // The surface vertices at the edge's ends and the weight of the second (PRT lighting).
    @location(6) @interpolate(flat) ends: vec2<u32>,
    @location(7) along: f32,
};

@vertex
fn vs_main(v: FinIn) -> FinOut {
    // p at the edge's midpoint: all four corners agree, so a faded-out fin is dropped whole.
    let p = dot(v.fin_normal, view_vector(v.center));
    let fade = max(0.0, 2.0 * abs(p) - 1.0) * frame.fin.x;
    let g = growth(v.normal, v.comb);
    // uv.y is 0 at the top of the fur (the fin texture's first row) and 1 at the skin.
    let position = v.position + (1.0 - v.uv.y) * frame.fur.x * v.length * g;
    var out: FinOut;
    out.clip = select(CULLED, clip_position(position), fade > 0.0);
    out.position = position;
    out.normal = v.normal;
    out.growth = g;
    out.uv = v.uv;
    out.color = v.color;
    out.fade = fade;
    out.ends = v.ends;
    out.along = v.along;
    return out;
}

@fragment
fn fs_main(f: FinOut) -> @location(0) vec4<f32> {
    let texel = textureSample(fin_texture, fin_sampler, f.uv);
    let opacity = f.fade * f.color.a;
    return shade_fin(f, texel.rgb * f.color.rgb * opacity, texel.a * opacity);
}
