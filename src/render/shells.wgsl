// Pass (c), the shells (Lengyel et al. 2001, §2.3): every shell in one instanced draw, instance
// order = inner to outer, each lifted in this vertex shader (§2.4, "Programmable vertex shaders").

@vertex
fn vs_main(v: SurfaceIn, @builtin(instance_index) instance: u32) -> SurfaceOut {
    // Shell i (1-based) of s shows layer round(i (L - 1) / s), so fewer shells keep the full
    // fur depth; integer rounding keeps the choice exact.
    let drawn = max(frame.counts.x, 1u);
    let top = frame.counts.y - 1u;
    let layer = ((instance + 1u) * top * 2u + drawn) / (2u * drawn);
    return surface_vertex(v, layer, true);
}

@fragment
fn fs_main(s: SurfaceOut) -> @location(0) vec4<f32> {
    let texel = surface_texel(s);
    let grad = uv_gradients(s.uv);
    // Bald faces (length 0 at every corner) draw nothing; the alpha test keeps empty texels from
    // writing depth over the layers still to come, and spares them the lighting.
    if (s.length <= 0.0 || texel.a * s.color.a < frame.fur.w) {
        discard;
    }
    return shade_surface(s, texel, s.color.a, grad);
}
