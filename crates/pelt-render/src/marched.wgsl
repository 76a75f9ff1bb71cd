// Pass (c), marched: the shells drawn as one hull, the outermost shell, whose fragments follow
// the view ray down through the shell layers below (the per-pixel ray of
// raycast-fur-virtual-planes §3, through Lengyel's horizontal layers instead of vertical planes).
// Each layer is read where the ray crosses its height, in the tile frame of the hull fragment
// (the surface taken as flat under it), and composited front to back; the march stops once the
// pixel is opaque, or where the ray passes the mesh's open border. The geometry is one mesh
// instead of one per shell, and the layers cost a texture read each instead of a rasterized
// triangle, which is what a CPU adapter pays for.
// Lighting is evaluated once per pixel (once per level during an LOD cross-fade): Kajiya-Kay at
// the layer where the composite passes half opacity, which has hair where the ray crosses it (an
// LOD group's hair direction read at its middle), with the Banks darkening, linear in height,
// applied to the composite exactly (the ambient's and the direct light's apart); PRT by the
// hair's mean transfer at the heights the composite holds (`Shown`).
// The ray, the composite and its lighting are `march.wgsl`'s.

#import pelt::common::{
    frame, shell_texture, tile_sampler, NO_LAYER, Layers, shell_layers, HEIGHT_NODES,
    hair_density, spread_out, level_shading_height,
}
#import pelt::surface::{Texels, MarchFrame}
#import pelt::march::{
    OPAQUE, Ray, ray_length, Marched, empty_march, composite, shown, lit, hull_fragment,
}
#ifdef PRT
#import pelt::surface_prt as model
#else
#import pelt::surface_kk as model
#endif

// How far, in texels of the mip read, the ray may move sideways through one composited group of
// layers of the LOD chain: while it stays within about a texel, the group's "over" composite
// (Lengyel §2.4) is what the ray would gather from its layers one by one.
const GROUP_SPREAD: f32 = 1.0;

// Whether a pixel may march the LOD chain's groups (`march_levels`): not under PRT, whose
// composite is lit by the mean transfer at the heights it holds (`Shown`), which
// a group's middle misstates; where the pixels switched to the coarsest group (head-on) the hot
// spot showed a bright disc.
#ifdef PRT
const MARCH_GROUPS: bool = false;
#else
const MARCH_GROUPS: bool = true;
#endif

// Whether an LOD cross-fade lights each level's composite apart and mixes the lit colors: under
// Kajiya-Kay a composite's light reads the hair tangent at the layer it shows, which differs
// between the two levels, so lighting their mix at one of them stepped as the fade passed half
// way (the short patch's LOD image by 10% between dolly frames 16% apart). PRT lights a composite
// by the heights it holds, which mix with it: one lighting serves.
#ifdef PRT
const LIGHT_EACH_LEVEL: bool = false;
#else
const LIGHT_EACH_LEVEL: bool = true;
#endif

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

@vertex
fn vs_main(v: model::SurfaceIn) -> model::SurfaceVarying {
    let hull = shell_layers(frame.counts.x - 1u);
    return model::surface_vertex(v, hull, f32(hull.height), true);
}

// During an LOD cross-fade (`fade`) the level drawn and the coarser one are composited apart,
// each with its own heights, and the two composites mixed: what each level's image would be,
// cross-faded. (Composited as one, each layer's texels mixed first, "over" is not linear in
// the mix: mid-fade the upper layers took more of the composite than either level gives them,
// lit higher in the fur, 5% bright under PRT with a side light.)
// `spread`: how the hull's triangle grows with height, which thins each layer's hair
// (`hair_density`).
fn march(s: model::SurfaceOut, ray: Ray, spread: vec2<f32>, lod: f32, fade: bool) -> Faded {
    let hull = shell_layers(frame.counts.x - 1u);
    var out = empty_march(hull, s.uv);
    // The coarser level's composite (opaque when no cross-fade runs: it never stops the march).
    var coarse = out;
    coarse.color.a = select(1.0, 0.0, fade);
    var i = frame.counts.x;
    loop {
        if (i == 0u || min(out.color.a, coarse.color.a) >= OPAQUE) {
            break;
        }
        i -= 1u;
        let layers = shell_layers(i);
        let t = ray_length(ray, f32(hull.height - layers.height));
        // The deeper layers lie further along the ray still; past the mesh's open border there
        // are none.
        if (t < 0.0 || t > ray.border) {
            break;
        }
        let uv = s.uv + ray.uv_rate * t;
        let texels = march_texels(uv, layers, lod, fade);
        let density = hair_density(spread, f32(layers.height) * frame.fur.y);
        let fine = spread_out(texels.fine, density) * s.color.a;
        // The instanced pass's alpha test: such a texel draws nothing.
        if (fine.a >= frame.fur.w) {
            out = composite(out, fine, layers, uv, texels.fine.a, model::march_heights(layers, false, lod));
        }
        // Thinned only when a cross-fade reads it: each `pow` counts on every step.
        if (fade) {
            let twin = spread_out(texels.coarse, density) * s.color.a;
            if (twin.a >= frame.fur.w) {
                coarse = composite(coarse, twin, layers, uv, texels.coarse.a,
                                   model::march_heights(layers, true, lod));
            }
        }
    }
    return Faded(out, coarse);
}

// What a march composites: the level drawn's, and during a cross-fade its coarser twin's.
struct Faded {
    fine: Marched,
    coarse: Marched,
};

// The composites `a` and `b` mixed by `t`, to be lit once (PRT, `LIGHT_EACH_LEVEL`); the layer
// shown is the one of the composite that weighs more.
fn mixed(a: Marched, b: Marched, t: f32) -> Marched {
    var m = a;
    if (t > 0.5) {
        m = b;
    }
    m.color = mix(a.color, b.color, t);
    m.raised = mix(a.raised, b.raised, t);
    for (var k = 0u; k < HEIGHT_NODES; k++) {
        m.nodes[k] = mix(a.nodes[k], b.nodes[k], t);
    }
    return m;
}

// The coarsest LOD level with two layers or more (the skin and one group of every hair layer):
// the first whose groups of 2^k layers hold the L - 1 above the skin.
fn top_level() -> u32 {
    var k = 0u;
    while ((1u << k) + 1u < frame.counts.y) {
        k += 1u;
    }
    return k;
}

// The coarsest level a pixel marches: groups of a quarter of the hair layers. A group is read
// and lit at its middle height; the two coarsest levels, one or two groups for the whole depth,
// put that height far from where the ray sees the hair (the short patch's single group 4% bright,
// its pair 6% dark against the march layer by layer), and as the mip level rose along a dolly
// the pixels switched to them together: the image without LOD stepped by 8%.
fn coarsest_march_level() -> u32 {
    return max(top_level(), 2u) - 2u;
}

// Layers of LOD level `k <= top_level()` of the volume (`frame.counts.y` layers at level 0): the
// skin and ⌈(L - 1) / 2^k⌉ groups (`pelt_core::volume::lod`).
fn level_count(k: u32) -> u32 {
    return 1u + ((frame.counts.y - 1u + (1u << k) - 1u) >> k);
}

// The coarsest level whose groups the ray crosses within GROUP_SPREAD texels, at most
// `coarsest_march_level`, for a march of the whole stack: head-on four composited groups stand
// for 32 layers, toward the limb it steps through every layer.
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
    return u32(clamp(select(k, 0.0, k != k), 0.0, f32(coarsest_march_level())));
}

// The march through the whole stack at LOD level `k`: its groups from the top down to group 1
// (level-0 layers 1 .. 2^k), each read and lit where the ray crosses its middle height. So 32
// shells take 1 to 32 reads. Level 0 is the march above, layer by layer.
fn march_levels(s: model::SurfaceOut, ray: Ray, spread: vec2<f32>, lod: f32, k: u32) -> Marched {
    let top = frame.counts.y - 1u;
    var base = 0u;
    for (var i = 0u; i < k; i++) {
        base += level_count(i);
    }
    var out = empty_march(Layers(top, top, NO_LAYER), s.uv);
    let step = 1u << k;
    var j = level_count(k) - 1u;
    loop {
        if (j == 0u || out.color.a >= OPAQUE) {
            break;
        }
        let lo = (j - 1u) * step + 1u;
        let hi = min(j * step, top);
        let layers = Layers((lo + hi) / 2u, base + j, NO_LAYER);
        let t = ray_length(ray, f32(top) - 0.5 * f32(lo + hi));
        // The deeper groups lie further along the ray still, as does the open border.
        if (t < 0.0 || t > ray.border) {
            break;
        }
        let uv = s.uv + ray.uv_rate * t;
        let texels = march_texels(uv, layers, lod, false);
        let middle = 0.5 * f32(lo + hi);
        let texel = spread_out(texels.fine, hair_density(spread, middle * frame.fur.y)) * s.color.a;
        if (texel.a >= frame.fur.w) {
            out = composite(out, texel, layers, uv, texels.fine.a, vec2<f32>(middle, middle * middle));
        }
        j -= 1u;
    }
    return out;
}

@fragment
fn fs_main(v: model::SurfaceVarying) -> @location(0) vec4<f32> {
    let h = hull_fragment(v);
    let s = h.s;
    let f = h.f;
    let ray = h.ray;
    let grad = h.grad;
    // Bald faces draw no shells.
    if (s.length <= 0.0) {
        discard;
    }
    let lod = march_lod(grad);
    var m: Marched;
    if (frame.fin.y > 0.0) {
        let faded = march(s, ray, f.spread, lod, true);
        if (LIGHT_EACH_LEVEL) {
            let color = mix(lit_march(s, f, grad, faded.fine, frame.lod.z),
                            lit_march(s, f, grad, faded.coarse, 2u * frame.lod.z), frame.fin.y);
            if (color.a <= 0.0) {
                discard;
            }
            return color;
        }
        m = mixed(faded.fine, faded.coarse, frame.fin.y);
    } else if (frame.counts.z == 0u && frame.counts.x + 1u == frame.counts.y && MARCH_GROUPS) {
        // The whole stack, no frame-wide LOD: each pixel picks its own level (its groups shown
        // at their middle already, which `lit_march` keeps without a frame-wide LOD).
        m = march_levels(s, ray, f.spread, lod, march_level(ray, lod));
    } else {
        m = march(s, ray, f.spread, lod, false).fine;
    }
    if (m.color.a <= 0.0) {
        discard;
    }
    return lit_march(s, f, grad, m, frame.lod.z);
}

// The composite `m` of a level whose groups hold `group` level-0 layers, lit where it shows its
// hair: the hair direction read at the shown group's middle, where the instanced shells read it
// (at its top, the tips, the short patch's marched LOD was 10% bright). Derived here from the
// layer shown rather than carried through the march: a wider composite, copied at every step,
// cost the 512² marched frame 26-41% on a CPU adapter. One layer, the lower of two middles:
// mixed between both, as the instanced shells do, ꟻLIP rose 0.005 on short fur.
fn lit_march(s: model::SurfaceOut, f: MarchFrame, grad: vec4<f32>, m: Marched,
             group: u32) -> vec4<f32> {
    var at = m.shown;
    at.height = u32(level_shading_height(at.height, group));
    return lit(s, f, m, model::march_light(s, f, m.uv, at, m.alpha, grad, shown(m)));
}
