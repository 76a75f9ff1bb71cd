// Fins under Kajiya-Kay lighting: the fin texture has no tangent map, its hair runs along the
// growth direction.

fn shade_fin(f: FinOut, albedo: vec3<f32>, alpha: f32) -> vec4<f32> {
    let n = unit_or(f.normal, vec3<f32>(0.0, 0.0, 1.0));
    let t = unit_or(f.growth, n);
    return shade(albedo, alpha, t, n, view_vector(f.position), 1.0 - f.uv.y);
}
