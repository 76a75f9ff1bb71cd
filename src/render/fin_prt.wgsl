// Fins under PRT lighting: the fin texture has no transfer of its own (prt-shell-fur §4 leaves
// fins to future work), so a fin row takes the mean transfer of the hair in the shell layers at
// its height, lit by its two ends' rotated lighting.

fn shade_fin(f: FinOut, albedo: vec3<f32>, alpha: f32) -> vec4<f32> {
    let ids = vec3<u32>(f.ends, f.ends.x);
    let w = vec3<f32>(1.0 - f.along, f.along, 0.0);
    return vec4<f32>(albedo * mean_radiance(ids, w, 1.0 - f.uv.y), alpha);
}
