// Hair lighting (Lengyel et al. 2001, §2.4): the modified Banks / Kajiya-Kay model
//   Ka + Kd (1 - u²)^(Pd/2) + Ks (1 - v²)^(Ps/2),  u = T·L, v = T·H,
// evaluated per fragment instead of through a 32 × 32 table, with Banks-style darkening toward
// the skin.

// Kajiya-Kay alone lights hair on the side of the body turned away from the light as brightly
// as the lit side; the body shadows it. A wrapped N·L fades the direct terms over a soft band
// around the terminator (wider than Lambert's, as light scatters through the fur).
const TERMINATOR_WRAP: f32 = 0.3;

// The hair lighting at one point with its highlight left as a multiple of the light color:
// `HairLight(scale, frame.light_color.rgb * shine)`, one float where a vertex passes it on.
struct HairTerms {
    scale: vec3<f32>,
    shine: f32,
};

// `height` is the share of the fur depth (0 at the skin, 1 at the top of the volume).
fn hair_terms(tangent: vec3<f32>, normal: vec3<f32>, view: vec3<f32>, height: f32) -> HairTerms {
    let l = frame.light_direction.xyz;
    let h = unit_or(l + view, normal);
    let u = dot(tangent, l);
    let v = dot(tangent, h);
    // The floor keeps pow's base positive (pow(0, y) is undefined in WGSL).
    let diffuse = pow(max(1.0 - u * u, 1e-8), 0.5 * frame.kajiya_kay.z);
    let specular = pow(max(1.0 - v * v, 1e-8), 0.5 * frame.kajiya_kay.w);
    let lit = clamp((dot(normal, l) + TERMINATOR_WRAP) / (1.0 + TERMINATOR_WRAP), 0.0, 1.0);
    let banks = 1.0 - frame.fur.z * (1.0 - clamp(height, 0.0, 1.0));
    return HairTerms((frame.ambient.rgb + frame.light_color.rgb * lit * (frame.kajiya_kay.x * diffuse)) * banks,
                     lit * (frame.kajiya_kay.y * specular) * banks);
}

// The hair lighting at one point (see `HairLight` and `hair_terms`).
fn hair_light(tangent: vec3<f32>, normal: vec3<f32>, view: vec3<f32>, height: f32) -> HairLight {
    let k = hair_terms(tangent, normal, view, height);
    return HairLight(k.scale, frame.light_color.rgb * k.shine);
}

// `albedo` is premultiplied by `alpha`; so is the result.
fn shade(albedo: vec3<f32>, alpha: f32, tangent: vec3<f32>, normal: vec3<f32>, view: vec3<f32>,
         height: f32) -> vec4<f32> {
    let k = hair_light(tangent, normal, view, height);
    return vec4<f32>(albedo * k.scale + alpha * k.add, alpha);
}

// The skin itself: an opaque surface under the hair roots (where the fur is painted away, the
// whole of what shows), lit by the wrapped N·L instead of the hair terms. Its tangent map holds
// the roots' mean direction, nearly the normal, which Kajiya-Kay would light darkest exactly
// where the light falls straight on. Banks-darkened like the roots above it.
fn shade_skin(albedo: vec3<f32>, normal: vec3<f32>) -> vec3<f32> {
    let l = frame.light_direction.xyz;
    let lit = clamp((dot(normal, l) + TERMINATOR_WRAP) / (1.0 + TERMINATOR_WRAP), 0.0, 1.0);
    let light = frame.light_color.rgb * (lit * frame.kajiya_kay.x);
    return albedo * (frame.ambient.rgb + light) * (1.0 - frame.fur.z);
}
