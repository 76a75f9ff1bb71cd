// Pass (c), marched: the shells drawn as one hull, the outermost shell, whose fragments follow
// the view ray down through the shell layers below (the per-pixel ray of
// raycast-fur-virtual-planes §3, through Lengyel's horizontal layers instead of vertical planes).
// Each layer is read where the ray crosses its height, in the tile frame of the hull fragment
// (the surface taken as flat under it), and composited front to back; the march stops once the
// pixel is opaque. The geometry is one mesh instead of one per shell, and the layers cost a
// texture read each instead of a rasterized triangle, which is what a CPU adapter pays for.
// Lighting is evaluated once per pixel, at the layer where the composite passes half opacity,
// which has hair where the ray crosses it; the Banks darkening, linear in height, is applied to
// the composite exactly (the ambient's and the direct light's apart), and PRT moves its transfer to the composite's mean height (`raised`).
// The lighting model's file defines `march_frame`, `march_light` and `march_banks`.

// The most ray length, in layer heights, that descends one layer: where a flat hull is seen
// nearly edge-on (beyond about 80°), the ray is bent down so that it still reaches the skin.
const MAX_RUN: f32 = 6.0;
// Opacity past which the layers below cannot change an 8-bit pixel.
const OPAQUE: f32 = 0.998;
// How far, in texels of the mip read, the ray may move sideways through one composited group of
// layers of the LOD chain: while it stays within about a texel, the group's "over" composite
// (Lengyel §2.4) is what the ray would gather from its layers one by one.
const GROUP_SPREAD: f32 = 1.0;

// The mip level of the shell texture for the whole march: the hull's footprint, rounded to one
// level (a single bilinear level costs half a trilinear read).
fn march_lod(grad: vec4<f32>) -> f32 {
    let texels = vec2<f32>(textureDimensions(shell_texture));
    let rho = max(length(grad.xy * texels), length(grad.zw * texels));
    return round(log2(max(rho, 1.0)));
}

// `fade`: whether an LOD cross-fade runs; a literal at each call, so that the march without one
// holds no second texture read (a CPU adapter would pay for it even when skipped).
fn march_texels(uv: vec2<f32>, layers: Layers, lod: f32, fade: bool) -> Texels {
    let fine = textureSampleLevel(shell_texture, tile_sampler, uv, layers.fine, lod);
    var coarse = vec4<f32>(0.0);
    if (fade && layers.coarse != NO_LAYER) {
        coarse = textureSampleLevel(shell_texture, tile_sampler, uv, layers.coarse, lod);
    }
    return Texels(fine, coarse);
}

// The view ray from a hull fragment, in the tile frame: `uv` moves `uv_rate` per object unit of
// ray, its height above the surface falls `fall` level-0 layers per unit and, where the surface
// curves away under it (a sphere's limb), rises back `bend` per unit² (the surface drops t²κ/2
// below the tangent plane). A ray whose height never reaches a layer leaves the fur first.
struct Ray {
    uv_rate: vec2<f32>,
    fall: f32,
    bend: f32,
    // Longest ray, per layer of drop, before it is bent down to the skin: MAX_RUN layer heights.
    cap: f32,
};

// `curvature`: the surface's normal curvature at the fragment, 0 where flat or concave.
fn march_ray(f: MarchFrame, curvature: f32) -> Ray {
    // Columns: object offset per unit of u, of v and of level-0 layer height.
    let a = f.dpdu;
    let b = f.dpdv;
    let c = f.up * frame.fur.y;
    let bc = cross(b, c);
    let det = dot(a, bc);
    let layer = length(c);
    if (!(abs(det) > 1e-30 && layer > 0.0)) {
        return Ray(vec2<f32>(0.0), 1.0, 0.0, 1.0);
    }
    // The ray into the surface in (u, v, height) per object unit: Cramer's rule.
    let w = -view_vector(f.position);
    let d = vec3<f32>(dot(bc, w), dot(cross(c, a), w), dot(cross(a, b), w)) / det;
    return Ray(d.xy, -d.z, 0.5 * curvature / layer, MAX_RUN * layer);
}

// Ray length to drop `drop` level-0 layers below the hull, or a negative value if it never does:
// the nearer root of bend·t² − fall·t + drop = 0, in the form that stays exact as bend → 0.
fn ray_length(r: Ray, drop: f32) -> f32 {
    let disc = r.fall * r.fall - 4.0 * r.bend * drop;
    if (drop <= 0.0) {
        return 0.0;
    }
    if (r.fall <= 0.0 || disc < 0.0) {
        // Flat and seen edge-on, the ray is bent down to the layer; curved, it has left the fur.
        return select(-1.0, r.cap * drop, r.bend <= 0.0);
    }
    return min(2.0 * drop / (r.fall + sqrt(disc)), r.cap * drop);
}

// The surface's curvature from screen derivatives of the normal and position (taken in uniform
// control flow): the larger of the two screen axes', where the normal turns away from the step.
fn surface_curvature(normal: vec3<f32>, position: vec3<f32>) -> f32 {
    let dpx = dpdx(position);
    let dpy = dpdy(position);
    let kx = dot(dpdx(normal), dpx) / max(dot(dpx, dpx), 1e-30);
    let ky = dot(dpdy(normal), dpy) / max(dot(dpy, dpy), 1e-30);
    return max(max(kx, ky), 0.0);
}

@vertex
fn vs_main(v: SurfaceIn) -> SurfaceVarying {
    return surface_vertex(v, shell_layers(frame.counts.x - 1u), true);
}

// What a march leaves: the composite (premultiplied, before the vertex color's rgb) and the layer
// lit for it, the one where the composite passes half opacity.
struct Marched {
    color: vec4<f32>,
    // Σ of each layer's share of `color` × its height (share of the fur depth): Banks darkening,
    // (1 - b) + b × height, of every layer composited is (1 - b) color + b raised.
    raised: vec4<f32>,
    shown: Layers,
    uv: vec2<f32>,
    // The shown layer's own texel opacity (level drawn).
    alpha: f32,
};

// `out` with `texel` (premultiplied, read at `uv` from `layers`, its level's own opacity
// `alpha`, standing `height` level-0 layers up) composited under it; the layer where the
// composite passes half opacity is the one lit.
fn composite(out: Marched, texel: vec4<f32>, layers: Layers, uv: vec2<f32>, alpha: f32,
             height: f32) -> Marched {
    var next = out;
    if (out.color.a < 0.5) {
        next.shown = layers;
        next.uv = uv;
        next.alpha = alpha;
    }
    let share = (1.0 - out.color.a) * texel;
    next.color += share;
    next.raised += share * (height * frame.fur.y);
    return next;
}

fn march(s: SurfaceOut, ray: Ray, lod: f32, fade: bool) -> Marched {
    let hull = shell_layers(frame.counts.x - 1u);
    var out = Marched(vec4<f32>(0.0), vec4<f32>(0.0), hull, s.uv, 1.0);
    var i = frame.counts.x;
    loop {
        if (i == 0u || out.color.a >= OPAQUE) {
            break;
        }
        i -= 1u;
        let layers = shell_layers(i);
        let t = ray_length(ray, f32(hull.height - layers.height));
        // The deeper layers lie further along the ray still.
        if (t < 0.0) {
            break;
        }
        let uv = s.uv + ray.uv_rate * t;
        let texels = march_texels(uv, layers, lod, fade);
        let texel = blended(texels) * s.color.a;
        // The instanced pass's alpha test: such a texel draws nothing.
        if (texel.a < frame.fur.w) {
            continue;
        }
        out = composite(out, texel, layers, uv, texels.fine.a, f32(layers.height));
    }
    return out;
}

// Layers of LOD level `k` of the volume (`frame.counts.y` layers at level 0): ⌈L / 2^k⌉.
fn level_count(k: u32) -> u32 {
    return (frame.counts.y + (1u << k) - 1u) >> k;
}

// The coarsest level whose groups the ray crosses within GROUP_SPREAD texels, for a march of the
// whole stack: head-on a few composited groups stand for 32 layers, toward the limb it steps
// through every layer. Level `k` needs a layer above its first (two layers), so `k` stops short
// of the single-layer level.
fn march_level(ray: Ray, lod: f32) -> u32 {
    let per_layer = ray_length(ray, 1.0);
    // A ray that leaves the fur within a layer (at the limb) reads the top layers one by one.
    if (per_layer < 0.0) {
        return 0u;
    }
    let texels = vec2<f32>(textureDimensions(shell_texture)) * exp2(-lod);
    let spread = length(ray.uv_rate * texels) * per_layer;
    let k = floor(log2(GROUP_SPREAD / spread));
    // Head-on (no spread, k = +inf) the coarsest level; NaN from a degenerate frame, the finest.
    return u32(clamp(select(k, 0.0, k != k), 0.0, f32(top_level())));
}

// The coarsest level with two layers or more.
fn top_level() -> u32 {
    var k = 0u;
    while (level_count(k + 1u) >= 2u) {
        k += 1u;
    }
    return k;
}

// The march through the whole stack from LOD level `k`: its groups from the top down to its
// group 1 (level-0 layers 2^k .. 2^(k+1) - 1), then group 1 of each finer level, which together
// hold level-0 layers 1 .. 2^k - 1 exactly. So 32 shells take 6 to 32 reads, each group read
// at its middle height. Level 0 is the march above, layer by layer.
fn march_levels(s: SurfaceOut, ray: Ray, lod: f32, k: u32) -> Marched {
    let top = frame.counts.y - 1u;
    var base = 0u;
    for (var i = 0u; i < k; i++) {
        base += level_count(i);
    }
    var out = Marched(vec4<f32>(0.0), vec4<f32>(0.0), Layers(top, top, NO_LAYER), s.uv, 1.0);
    var m = k;
    var j = level_count(k) - 1u;
    loop {
        if (out.color.a >= OPAQUE) {
            break;
        }
        let lo = j << m;
        let hi = min(lo + (1u << m) - 1u, top);
        let layers = Layers((lo + hi) / 2u, base + j, NO_LAYER);
        let t = ray_length(ray, f32(top) - 0.5 * f32(lo + hi));
        // The deeper groups lie further along the ray still.
        if (t < 0.0) {
            break;
        }
        let uv = s.uv + ray.uv_rate * t;
        let texels = march_texels(uv, layers, lod, false);
        let texel = texels.fine * s.color.a;
        if (texel.a >= frame.fur.w) {
            out = composite(out, texel, layers, uv, texels.fine.a, 0.5 * f32(lo + hi));
        }
        if (j > 1u) {
            j -= 1u;
        } else if (m > 0u) {
            m -= 1u;
            base -= level_count(m);
            j = 1u;
        } else {
            break;
        }
    }
    return out;
}

@fragment
fn fs_main(v: SurfaceVarying) -> @location(0) vec4<f32> {
    let s = surface_fragment(v);
    let grad = uv_gradients(s.uv);
    let f = march_frame(s);
    let curvature = surface_curvature(f.normal, f.position);
    // Bald faces draw no shells.
    if (s.length <= 0.0) {
        discard;
    }
    let ray = march_ray(f, curvature);
    let lod = march_lod(grad);
    var m: Marched;
    if (frame.fin.y > 0.0) {
        m = march(s, ray, lod, true);
    } else if (frame.counts.z == 0u && frame.counts.x + 1u == frame.counts.y) {
        // The whole stack, no frame-wide LOD: each pixel picks its own level.
        m = march_levels(s, ray, lod, march_level(ray, lod));
    } else {
        m = march(s, ray, lod, false);
    }
    if (m.color.a <= 0.0) {
        discard;
    }
    let mean = m.raised.a / max(m.color.a, 1e-6);
    let k = march_light(s, f, m.uv, m.shown, m.alpha, grad, mean);
    let b = march_banks(f);
    let ambient = (1.0 - b.x) * m.color.rgb + b.x * m.raised.rgb;
    let c = (1.0 - b.y) * m.color + b.y * m.raised;
    return vec4<f32>((ambient * k.ambient + c.rgb * k.scale) * s.color.rgb + c.a * k.add,
                     m.color.a);
}
