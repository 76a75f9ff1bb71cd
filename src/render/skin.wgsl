// Pass (a), the skin (Lengyel et al. 2001, §2.3): the mesh itself, opaque, textured with layer 0
// of the shell texture times the vertex color; it fills the depth buffer.

@vertex
fn vs_main(v: SurfaceIn) -> SurfaceOut {
    // The skin is lit as under fur of length multiplier 1, whatever the painted length: painting
    // lengths (or baldness) changes only the fins and shells, never the skin.
    return surface_vertex(v, skin_layers(), false);
}

@fragment
fn fs_main(s: SurfaceOut) -> @location(0) vec4<f32> {
    let c = shade_surface(s, surface_texels(s), 1.0, uv_gradients(s.uv));
    return vec4<f32>(c.rgb, 1.0);
}
