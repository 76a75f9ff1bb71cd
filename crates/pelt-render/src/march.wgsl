#define_import_path pelt::march

#import pelt::common::{
    frame, Layers, HairLight, view_vector, HEIGHT_NODES, Shown, unit_or, curvature_along,
}
#import pelt::surface::{uv_gradients, MarchFrame}
#ifdef PRT
#import pelt::surface_prt as model
#else
#import pelt::surface_kk as model
#endif

// What the marched shells (`marched.wgsl`) and the virtual planes (`planes.wgsl`) share: a hull
// fragment's view ray in the tile frame, the front-to-back composite it gathers, and how the
// composite is lit once per pixel with the Banks darkening applied exactly. The lighting model
// (`light_model.wgsl`) provides `march_frame`, `march_light`, `plane_light` and `march_banks`.

// The most ray length, in layer heights, that descends one layer: where a flat hull is seen
// nearly edge-on (beyond about 80°), the ray is bent down so that it still reaches the skin.
const MAX_RUN: f32 = 6.0;
// Opacity past which the layers below cannot change an 8-bit pixel.
const OPAQUE: f32 = 0.998;

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
    // Ray length to the mesh's open border (`border_run`), NO_BORDER where it never gets there.
    border: f32,
};

// `Ray::border` of a ray that never leaves the mesh.
const NO_BORDER: f32 = 1e30;

// The ray bends by the surface's normal curvature along the ray's own lateral direction
// (`curvature_along`, 0 where flat or concave). The larger of the screen axes' had bent it by the
// curvature across a crease or a torus's tube seen along its flat direction, letting it out
// through the well-lit tips early: marched over instanced under PRT, long-furred Suzanne from the
// side and above 1.25 and 1.24, the torus 1.23 and 1.22 (1.13, 1.19; 1.04, 1.08 by the ray's).
fn march_ray(f: MarchFrame) -> Ray {
    // Columns: object offset per unit of u, of v and of level-0 layer height.
    let a = f.dpdu;
    let b = f.dpdv;
    let c = f.up * frame.fur.y;
    let bc = cross(b, c);
    let det = dot(a, bc);
    let layer = length(c);
    if (!(abs(det) > 1e-30 && layer > 0.0)) {
        return Ray(vec2<f32>(0.0), 1.0, 0.0, 1.0, NO_BORDER);
    }
    // The ray into the surface in (u, v, height) per object unit: Cramer's rule.
    let w = -view_vector(f.position);
    let d = vec3<f32>(dot(bc, w), dot(cross(c, a), w), dot(cross(a, b), w)) / det;
    let n = unit_or(f.normal, c / layer);
    let lateral = w - n * dot(n, w);
    let bend = 0.5 * curvature_along(f.steps, lateral);
    return Ray(d.xy, -d.z, bend / layer, MAX_RUN * layer, NO_BORDER);
}

// Ray length from the hull fragment of `f` to the mesh's open border, its tile UV moving
// `uv_rate` per unit of ray, `grad` the tile UV's screen derivatives. Each shell is the mesh
// lifted and ends where the mesh does, so a march past it gathered layers that are not there
// (marched over instanced, the long patch's coverage had been 5% more). Each of the two border
// distances is affine over a triangle (exactly so beside one straight side), so its gradient in
// the tile is its screen steps mapped back through the UV's screen Jacobian, and the ray stops
// where the first of them runs out: by the nearest side alone, a ray toward a corner went on
// past the other side.
fn border_run(f: MarchFrame, grad: vec4<f32>, uv_rate: vec2<f32>) -> f32 {
    return min(side_run(f.border.x, f.border_steps.xz, grad, uv_rate),
               side_run(f.border.y, f.border_steps.yw, grad, uv_rate));
}

// Ray length to where a distance `border` with screen steps `steps` (d/dx, d/dy) falls to 0.
fn side_run(border: f32, steps: vec2<f32>, grad: vec4<f32>, uv_rate: vec2<f32>) -> f32 {
    // d(border)/dx = ∇·(du/dx, dv/dx), likewise in y: solved for ∇ by Cramer's rule.
    let det = grad.x * grad.w - grad.y * grad.z;
    if (!(abs(det) > 1e-30)) {
        return NO_BORDER;
    }
    let gradient = vec2<f32>(steps.x * grad.w - grad.y * steps.y,
                             grad.x * steps.y - grad.z * steps.x) / det;
    let closing = -dot(gradient, uv_rate);
    // Along or away from the side the march never meets it; nor on a triangle with the border at
    // all three corners (0 everywhere, no gradient); a closed piece's distance is constant.
    if (!(closing > 0.0)) {
        return NO_BORDER;
    }
    return max(border, 0.0) / closing;
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

// What a march leaves: the composite (premultiplied, before the vertex color's rgb) and the layer
// lit for it, the one where the composite passes half opacity.
struct Marched {
    color: vec4<f32>,
    // Σ of each layer's share of `color` × its height (share of the fur depth): Banks darkening,
    // (1 - b) + b × height, of every layer composited is (1 - b) color + b raised.
    raised: vec4<f32>,
    // `color` split among the HEIGHT_NODES heights, each layer's share between the two around
    // its height (PRT: each node is lit by the hair's mean transfer there, `Shown`).
    nodes: array<vec3<f32>, HEIGHT_NODES>,
    shown: Layers,
    uv: vec2<f32>,
    // The shown layer's own texel opacity (level drawn).
    alpha: f32,
};

// A march that has composited nothing yet, its lit layer `shown` read at `uv`.
fn empty_march(shown: Layers, uv: vec2<f32>) -> Marched {
    var m: Marched;
    m.shown = shown;
    m.uv = uv;
    m.alpha = 1.0;
    return m;
}

// `color` added to the nodes of `m` around `height` (share of the fur depth), split between the
// two linearly. Every node is visited with its constant index: an array indexed at run time is
// kept in memory by a CPU adapter (the marched PRT frame: 544 ms against 352 ms).
fn deposit(m: ptr<function, Marched>, height: f32, color: vec3<f32>) {
    let at = clamp(height, 0.0, 1.0) * f32(HEIGHT_NODES - 1u);
    for (var j = 0u; j < HEIGHT_NODES; j++) {
        (*m).nodes[j] += max(1.0 - abs(at - f32(j)), 0.0) * color;
    }
}

// `out` with `texel` (premultiplied, read at `uv` from `layers`, its level's own opacity
// `alpha`) composited under it; `heights`: the mean and mean square of the level-0 heights (in
// layers) of the hair the texel shows (a level-0 layer's own height h: (h, h²); an LOD
// composite's, the model's `march_heights`). The layer where the composite passes half opacity
// is the one lit.
fn composite(out: Marched, texel: vec4<f32>, layers: Layers, uv: vec2<f32>, alpha: f32,
             heights: vec2<f32>) -> Marched {
    var next = out;
    if (out.color.a < 0.5) {
        next.shown = layers;
        next.uv = uv;
        next.alpha = alpha;
    }
    let share = (1.0 - out.color.a) * texel;
    next.color += share;
    next.raised += share * (heights.x * frame.fur.y);
#ifdef PRT
    // An LOD composite's hair spreads over its members' heights: half at the mean ± the
    // deviation.
    let deviation = sqrt(max(heights.y - heights.x * heights.x, 0.0));
    if (deviation > 0.0) {
        deposit(&next, (heights.x - deviation) * frame.fur.y, 0.5 * share.rgb);
        deposit(&next, (heights.x + deviation) * frame.fur.y, 0.5 * share.rgb);
    } else {
        deposit(&next, heights.x * frame.fur.y, share.rgb);
    }
#endif
    return next;
}

// What `m` holds, for its light: the mean height of its layers, weighed by what it shows of
// each, and its color by height.
fn shown(m: Marched) -> Shown {
    return Shown(m.raised.a / max(m.color.a, 1e-6), m.nodes);
}

// The composite `m` lit by `k`: the Banks darkening, linear in height, applied to the composite
// exactly (the ambient's and the direct light's apart), then the vertex color.
fn lit(s: model::SurfaceOut, f: MarchFrame, m: Marched, k: HairLight) -> vec4<f32> {
    let b = model::march_banks(s, f);
    let ambient = (1.0 - b.x) * m.color.rgb + b.x * m.raised.rgb;
    let c = (1.0 - b.y) * m.color + b.y * m.raised;
    return vec4<f32>((ambient * k.ambient + c.rgb * k.scale) * s.color.rgb + c.a * k.add,
                     m.color.a);
}

// The mip level of a tile-wide texture `texels` across at the footprint `grad` (screen
// derivatives of the tile UV).
fn footprint_lod(grad: vec4<f32>, texels: f32) -> f32 {
    return log2(max(max(length(grad.xy), length(grad.zw)) * texels, 1.0));
}

// A hull fragment: its surface, tile-UV derivatives, frame and view ray. Called first in a
// fragment shader: the derivatives need uniform control flow, before any discard.
struct HullFragment {
    s: model::SurfaceOut,
    grad: vec4<f32>,
    f: MarchFrame,
    ray: Ray,
};

fn hull_fragment(v: model::SurfaceVarying) -> HullFragment {
    let s = model::surface_fragment(v);
    let grad = uv_gradients(s.uv);
    let f = model::march_frame(s);
    var ray = march_ray(f);
    ray.border = border_run(f, grad, ray.uv_rate);
    return HullFragment(s, grad, f, ray);
}
