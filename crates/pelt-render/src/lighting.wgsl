#define_import_path pelt::lighting

#import pelt::common::{frame, HairLight, unit_or, shared_path, TERMINATOR_WRAP}

// Hair lighting (Lengyel et al. 2001, §2.4): the modified Banks / Kajiya-Kay model
//   Ka + Kd (1 - u²)^(Pd/2) + Ks (1 - v²)^(Ps/2),  u = T·L, v = T·H,
// evaluated per fragment instead of through a 32 × 32 table, with Banks-style darkening toward
// the skin.

// Kajiya-Kay alone lights hair on the side of the body turned away from the light as brightly
// as the lit side; the body shadows it. A wrapped N·L fades the direct terms over a soft band
// around the terminator (wider than Lambert's, as light scatters through the fur). Like the
// fur's own shadow below, the body's falls on nothing the eye sees when the light comes from the
// eye: it fades at the hot spot too (under a light from the eye it had darkened the fur by a
// quarter on average, most at the rim, where the reference's hair is lit brightest).
// The band is where hair standing `h` above a surface curving at κ still sees past its terminator:
// √(2 h κ) in N·L (a sphere's hair tip of radius R + h sees √(2h/R) past it), at most
// TERMINATOR_WRAP (`common.wgsl`). So a flat surface has none: under a grazing sun the flat
// patch's fur was 6× the reference's, lit through hair that shadows it.

// The wrap at a surface of `curvature` (`surface_curvature`) under fur `height` object units deep.
fn terminator_wrap(curvature: f32, height: f32) -> f32 {
    return min(sqrt(2.0 * max(height, 0.0) * curvature), TERMINATOR_WRAP);
}

// Banks darkening (Lengyel §2.4) is linear in height, 1 − b (1 − h): none at the tips, 1 − b at
// the skin. `frame.fur.z` is b for a light straight down the growth direction. A slanted light
// crosses 1/cos as much fur to reach the skin, so its darkening there is (1 − b)^(1/cos), as
// Beer–Lambert has it; and the closer the light comes to the eye's direction, the more of its
// path is the view ray's own, known clear (the hot spot, Hapke's shadow hiding): the exponent
// falls to 0 as the light meets the view. The ambient light arrives from every direction and
// keeps b. Hair painted `length` times as long crosses `length` times as much fur, so every
// exponent is multiplied by it: bald skin (length 0) is not darkened at all, as the reference's
// bare skin is not (it had been darkened as under fur of length 1: by the default b = 0.15
// under the ambient light, 0.85^(1/cos) under a slanted sun).
// Smallest cosine a light's slant is taken at: past the terminator the wrapped N·L fades it.
const MIN_SLANT_COS: f32 = 0.1;

// The Banks strengths: x for the ambient light, y for the light from `light` seen from `view`,
// under hair of painted `hair_length` (the multiplier of the fur depth).
fn banks_strengths(normal: vec3<f32>, light: vec3<f32>, view: vec3<f32>,
                   hair_length: f32) -> vec2<f32> {
    let b = clamp(frame.fur.z, 0.0, 1.0);
    let fur = max(hair_length, 0.0);
    let slant = 1.0 / max(dot(normal, light), MIN_SLANT_COS);
    let direct = 1.0 - pow(max(1.0 - b, 1e-8), slant * (1.0 - shared_path(light, view)) * fur);
    // b itself at length 1, not pow's approximation of it.
    let ambient = select(1.0 - pow(max(1.0 - b, 1e-8), fur), b, fur == 1.0);
    return vec2<f32>(ambient, direct);
}

// Banks darkening of strength `b` at `height` (share of the fur depth).
fn banks_at(b: f32, height: f32) -> f32 {
    return 1.0 - b * (1.0 - clamp(height, 0.0, 1.0));
}

// The hair lighting at one point before Banks darkening, split by what darkens it (see
// `banks_strengths`): `ambient`, and the direct light's `direct` and highlight `shine` (× the
// light color).
struct HairParts {
    ambient: vec3<f32>,
    direct: vec3<f32>,
    shine: f32,
};

// Goldman's directional attenuation (Fake fur rendering, 1997): κ is the cosine between the
// planes that hold the hair with the light and with the eye, 1 when the light falls on the side
// of the hair that is seen (reflected), −1 when it shines through it toward the eye
// (transmitted). Where either plane is undefined (the hair points at the light or the eye), κ is
// 0 and the two weigh alike.
fn directional_attenuation(tangent: vec3<f32>, light: vec3<f32>, view: vec3<f32>) -> f32 {
    let a = cross(tangent, light);
    let b = cross(tangent, view);
    let kappa = dot(a, b) / max(length(a) * length(b), 1e-12);
    return 0.5 * (1.0 + kappa) * frame.goldman.x + 0.5 * (1.0 - kappa) * frame.goldman.y;
}

// The ambient light at a surface facing `normal`: brighter where the sky is (KajiyaKay::ambient_gradient).
fn ambient_at(normal: vec3<f32>) -> vec3<f32> {
    let g = frame.ambient_gradient;
    let a = frame.ambient.rgb + normal.x * g[0].rgb + normal.y * g[1].rgb + normal.z * g[2].rgb;
    return max(a, vec3<f32>(0.0));
}

// `wrap`: the terminator band's width (`terminator_wrap`); `shadow`: the share of the light past
// the body (`body_shadow`). The hot spot does not clear it: a body's shadow is as wide as the
// body, and the map already finds it where the eye sees it, whereas the hot spot's width is the
// hair's.
fn hair_parts(tangent: vec3<f32>, normal: vec3<f32>, view: vec3<f32>, wrap: f32,
              shadow: f32) -> HairParts {
    let u = dot(tangent, frame.light_direction.xyz);
    let v = dot(tangent, half_vector(normal, view));
    return spread_hair_parts(tangent, vec2<f32>(u * u, v * v), normal, view, wrap, shadow);
}

// The Kajiya–Kay half vector between the light and `view` (`normal` where they cancel).
fn half_vector(normal: vec3<f32>, view: vec3<f32>) -> vec3<f32> {
    return unit_or(frame.light_direction.xyz + view, normal);
}

// `hair_parts` over hair whose mean direction is `tangent` and whose squared cosines to the light
// and to the half vector are `squares` on average ((T·L)², (T·H)²): the terms taken at the mean
// square, where one tangent standing for spread hair had lit it not at all along the light.
fn spread_hair_parts(tangent: vec3<f32>, squares: vec2<f32>, normal: vec3<f32>, view: vec3<f32>,
                     wrap: f32, shadow: f32) -> HairParts {
    let l = frame.light_direction.xyz;
    // The floor keeps pow's base positive (pow(0, y) is undefined in WGSL).
    let diffuse = pow(max(1.0 - squares.x, 1e-8), 0.5 * frame.kajiya_kay.z);
    let specular = pow(max(1.0 - squares.y, 1e-8), 0.5 * frame.kajiya_kay.w);
    let body = clamp((dot(normal, l) + wrap) / (1.0 + wrap), 0.0, 1.0);
    let lit = mix(body, 1.0, shared_path(l, view)) * shadow
        * directional_attenuation(tangent, l, view);
    return HairParts(ambient_at(normal), frame.light_color.rgb * lit * (frame.kajiya_kay.x * diffuse),
                     lit * (frame.kajiya_kay.y * specular));
}

// The hair lighting at one point with its highlight left as a multiple of the light color:
// `HairLight(scale, frame.light_color.rgb * shine)`, one float where a vertex passes it on.
struct HairTerms {
    scale: vec3<f32>,
    shine: f32,
};

// `height` is the share of the fur depth (0 at the skin, 1 at the top of the volume),
// `hair_length` the hair's painted length multiplier.
fn hair_terms(tangent: vec3<f32>, normal: vec3<f32>, view: vec3<f32>, height: f32,
              hair_length: f32, wrap: f32, shadow: f32) -> HairTerms {
    return parts_terms(hair_parts(tangent, normal, view, wrap, shadow), normal, view, height,
                       hair_length);
}

// `hair_terms` of the parts `p` (`hair_parts`, `spread_hair_parts`).
fn parts_terms(p: HairParts, normal: vec3<f32>, view: vec3<f32>, height: f32,
               hair_length: f32) -> HairTerms {
    let b = banks_strengths(normal, frame.light_direction.xyz, view, hair_length);
    let direct = banks_at(b.y, height);
    return HairTerms(p.ambient * banks_at(b.x, height) + p.direct * direct, p.shine * direct);
}

// The hair lighting at one point (see `HairLight` and `hair_terms`).
fn hair_light(tangent: vec3<f32>, normal: vec3<f32>, view: vec3<f32>, height: f32,
              hair_length: f32, wrap: f32, shadow: f32) -> HairLight {
    let k = hair_terms(tangent, normal, view, height, hair_length, wrap, shadow);
    return HairLight(vec3<f32>(0.0), k.scale, frame.light_color.rgb * k.shine);
}

// `albedo` is premultiplied by `alpha`; so is the result.
fn shade(albedo: vec3<f32>, alpha: f32, tangent: vec3<f32>, normal: vec3<f32>, view: vec3<f32>,
         height: f32, hair_length: f32, wrap: f32, shadow: f32) -> vec4<f32> {
    let k = hair_light(tangent, normal, view, height, hair_length, wrap, shadow);
    return vec4<f32>(albedo * k.scale + alpha * k.add, alpha);
}

// The skin itself: an opaque surface under the hair roots (where the fur is painted away, the
// whole of what shows), lit by the wrapped N·L instead of the hair terms. Its tangent map holds
// the roots' mean direction, nearly the normal, which Kajiya-Kay would light darkest exactly
// where the light falls straight on. Banks-darkened like the roots above it, by the fur of
// painted `hair_length` that stands over it. A Lambertian surface: Kd scales the sky's light as
// it does the sun's (the reference's skin; the ambient alone unscaled had lit bald skin under a
// sky at 1.155 of it).
fn shade_skin(albedo: vec3<f32>, normal: vec3<f32>, view: vec3<f32>, hair_length: f32, wrap: f32,
              shadow: f32) -> vec3<f32> {
    let l = frame.light_direction.xyz;
    let lit = clamp((dot(normal, l) + wrap) / (1.0 + wrap), 0.0, 1.0) * shadow;
    let b = banks_strengths(normal, l, view, hair_length);
    let light = ambient_at(normal) * (1.0 - b.x) + frame.light_color.rgb * (lit * (1.0 - b.y));
    return albedo * (frame.kajiya_kay.x * light);
}
