#define_import_path pelt::common

// Shared by every fur pass: the frame's uniforms, the scene's textures, small geometry helpers
// and the fins' texture read.
// All geometry and lighting are in object space (the mesh's own space).

#import pelt::body_shadow::map_visibility

struct Frame {
    view_proj: mat4x4<f32>,
    // The eye: w = 1 its position (perspective), w = 0 the unit direction toward it (orthographic).
    eye: vec4<f32>,
    // xyz: unit direction toward the light; w: under PRT its share of the light, which its hot
    // spot clears of the transfer's shadow (`LightingFrame::hot_spot_share`).
    light_direction: vec4<f32>,
    light_color: vec4<f32>,
    ambient: vec4<f32>,
    // Kajiya-Kay Kd, Ks, Pd, Ps.
    kajiya_kay: vec4<f32>,
    // x: fur depth (object units at length 1), y: layer spacing (share of the fur depth),
    // z: Banks self-shadow strength, w: alpha-test threshold of the shells.
    fur: vec4<f32>,
    // x: fin opacity, y: LOD cross-fade toward the coarser level (0 without LOD), z: the
    // geometric level's fin spacing over the full mesh's (1 for the full mesh).
    fin: vec4<f32>,
    // x: shells drawn, y: layers of the volume (level 0), z: 1 when LOD picks the layers, w: the
    // coarser level's first entry in `stand`.
    counts: vec4<u32>,
    // LOD: x first array layer of the level drawn, y of the next coarser level, z level-0
    // layers per group of the level drawn (2^k), w layers of the next coarser level (0: none).
    lod: vec4<u32>,
    // PRT: x coefficients n², y transfer textures, z array layers per transfer texture,
    // w layers of the volume (the fins' table of layer means).
    prt: vec4<u32>,
    // Guard strands: x, y the target's size in pixels, z the LOD's narrowest strand in pixels
    // (0: no LOD), w the smallest share of strands the LOD keeps.
    strand: vec4<f32>,
    // x: height bands n (strand draws n + 1), y: segments drawn per strand, z: flags (1: one
    // band holds every fragment, 2: stochastic coverage).
    strand_counts: vec4<u32>,
    // Virtual planes: x planes per family N, y the loop limit, zw the planes' lean (tile units
    // across per fur depth up).
    planes: vec4<f32>,
    // Kajiya-Kay: x Goldman's ρ_reflect, y ρ_transmit.
    goldman: vec4<f32>,
    // Kajiya-Kay: the ambient's change per unit of the normal's x, y and z (rgb).
    ambient_gradient: array<vec4<f32>, 3>,
    // The body's shadow map (`body_shadow.wgsl`): object space to the light's clip space, and x 1
    // when the map is drawn, y the normal offset (object units), z the depth bias.
    light_view_proj: mat4x4<f32>,
    shadow: vec4<f32>,
    // The hair directions' second moment E[d dᵀ] in the tile frame (`tangent_spread.rs`):
    // (xx, yy, zz, xy), (xz, yz, 0, 0); zero without hair.
    fin_tangents: array<vec4<f32>, 2>,
    // LOD: the level-0 height (in layers) each layer of the drawn level stands at (none at level
    // 0, whose layers stand at their own), then from `counts.w` on the next coarser level's
    // (`stand_heights.rs`).
    stand: array<vec4<f32>, 64>,
};

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var shell_texture: texture_2d_array<f32>;
@group(0) @binding(2) var tangent_texture: texture_2d_array<f32>;
@group(0) @binding(3) var fin_texture: texture_2d<f32>;
@group(0) @binding(4) var tile_sampler: sampler;
@group(0) @binding(5) var fin_sampler: sampler;
// The skin's vertices, SurfaceVertex rows of SKIN_FLOATS floats: position at 0, normal 3, dP/du
// 6, dP/dv 9, uv 12, comb 14. The fins read their ends from them and PRT's passes pull their
// corners from them, so that a pose, which rewrites them alone, moves everything drawn.
@group(0) @binding(6) var<storage, read> skin_vertices: array<f32>;
// Binding 7, the virtual planes' slices, is `planes.wgsl`'s. The body's shadow map and its
// comparison sampler (`body_shadow.wgsl`).
@group(0) @binding(8) var shadow_map: texture_depth_2d;
@group(0) @binding(9) var shadow_sampler: sampler_comparison;

// Widest band past the terminator, in N·L, that Kajiya–Kay's wrapped N·L lights
// (`lighting.wgsl` `terminator_wrap`).
const TERMINATOR_WRAP: f32 = 0.3;

// The share of the directional light that the body lets reach `position` (`map_visibility`).
// A surface turned from the light past the widest terminator band is the body's own shadow: no
// read (a CPU adapter pays for each).
fn body_shadow(position: vec3<f32>, normal: vec3<f32>) -> f32 {
    if (frame.shadow.x != 0.0 && dot(normal, frame.light_direction.xyz) <= -TERMINATOR_WRAP) {
        return 0.0;
    }
    return map_visibility(shadow_map, shadow_sampler, frame.light_view_proj, frame.shadow,
                          position, normal);
}

// `SurfaceVertex` rows: position, normal, dP/du, dP/dv, uv, comb, border distances.
const SKIN_FLOATS: u32 = 19u;

// The vec3 at float `offset` of skin vertex `vertex`.
fn skin_vec3(vertex: u32, offset: u32) -> vec3<f32> {
    let b = vertex * SKIN_FLOATS + offset;
    return vec3<f32>(skin_vertices[b], skin_vertices[b + 1u], skin_vertices[b + 2u]);
}

// A layer index meaning "none" (an odd shell has nothing in the next coarser level).
const NO_LAYER: u32 = 0xffffffffu;

// The layers a skin or shell vertex shows: `height` in level-0 layers (where it stands, which
// tangent map layer lights it), `fine` the shell array layer drawn, `coarse` the array layer
// cross-faded in from the next coarser level (or NO_LAYER).
struct Layers {
    height: u32,
    fine: u32,
    coarse: u32,
};

// The skin: layer 0 of the level drawn, fading into layer 0 of the next one.
fn skin_layers() -> Layers {
    return Layers(0u, frame.lod.x, select(NO_LAYER, frame.lod.y, frame.counts.z == 1u));
}

// Shell `instance + 1`. With LOD, group j of the level drawn (level-0 layers (j - 1) 2^k + 1 ..=
// j 2^k) has its top as height, min(j 2^k, L - 1) (where it stands is `shell_stand`'s), and
// fades into group j / 2 of the next level, whose top is the same: nothing for odd j but the
// last, whose twin is itself, nor into a last level of one layer (the skin with everything over
// it). Without, shell i (1-based) of s shows layer round(i (L - 1) / s), so fewer shells keep
// the full fur depth. The quotient is estimated in f32 (an integer division runs lane by lane
// on a CPU adapter, and the marched shells call this per layer and pixel), which lands within
// one of it, and settled exactly by two integer multiplications (a float division need not
// round correctly).
fn shell_layers(instance: u32) -> Layers {
    let j = instance + 1u;
    if (frame.counts.z == 1u) {
        let twin = frame.lod.w > 1u && (j % 2u == 0u || j == frame.counts.x);
        let coarse = select(NO_LAYER, frame.lod.y + (j + 1u) / 2u, twin);
        return Layers(min(j * frame.lod.z, frame.counts.y - 1u), frame.lod.x + j, coarse);
    }
    let drawn = max(frame.counts.x, 1u);
    let top = frame.counts.y - 1u;
    let n = j * top * 2u + drawn;
    let d = 2u * drawn;
    var layer = u32(f32(n) / f32(d));
    layer = select(layer, layer - 1u, layer * d > n);
    layer = select(layer, layer + 1u, (layer + 1u) * d <= n);
    return Layers(layer, layer, NO_LAYER);
}

// The level-0 height, in layers, at which a shell of `layers` is lit: the middle of the group it
// composites (Lengyel §2.4; Banks darkening is linear in height), moved toward its coarser
// twin's middle as the LOD cross-fade runs. Without LOD, a shell's own layer. (Lit where a group
// of alike layers would show its hair on the whole, nearer its top, the LOD strayed up to 7%
// from the all-shells image on the short-furred scenes: their tips are sparser.)
fn shading_height(layers: Layers) -> f32 {
    let middle = level_shading_height(layers.height, frame.lod.z);
    if (layers.coarse == NO_LAYER || frame.fin.y <= 0.0) {
        return middle;
    }
    return mix(middle, level_shading_height(layers.height, 2u * frame.lod.z), frame.fin.y);
}

// `shading_height` within one level, whose groups hold `step` level-0 layers: the middle of the
// group whose top is layer `top`; without LOD, or at the skin, `top` itself.
fn level_shading_height(top: u32, step: u32) -> f32 {
    if (frame.counts.z != 1u || top == 0u) {
        return f32(top);
    }
    return group_middle(top, step);
}

// The level-0 height, in layers, at which a shell of `layers` stands: a level-0 layer at its own,
// an LOD composite where its hair covers the silhouette as the layers it holds would
// (`stand_heights.rs`), moved toward its coarser twin's as the cross-fade runs.
fn shell_stand(layers: Layers) -> f32 {
    if (frame.counts.z != 1u || layers.height == 0u) {
        return f32(layers.height);
    }
    var fine = f32(layers.height);
    if (frame.lod.x > 0u) {
        fine = stand_entry(layers.fine - frame.lod.x);
    }
    if (layers.coarse == NO_LAYER || frame.fin.y <= 0.0) {
        return fine;
    }
    return mix(fine, stand_entry(frame.counts.w + layers.coarse - frame.lod.y), frame.fin.y);
}

// Entry `i` of `frame.stand`.
fn stand_entry(i: u32) -> f32 {
    return frame.stand[i / 4u][i % 4u];
}

// The middle height of the group of `step` level-0 layers whose top is layer `top > 0`.
fn group_middle(top: u32, step: u32) -> f32 {
    return 0.5 * f32(top + ((top - 1u) / step) * step + 1u);
}

// Heights (shares of the fur depth, 0 the skin, 1 the top layer) at which PRT lights a marched
// composite: HEIGHT_NODES evenly spaced, each layer's color split between the two around it.
const HEIGHT_NODES: u32 = 9u;

// What a marched composite holds, for its light (`march.wgsl` `shown`).
struct Shown {
    // The mean height of its hair, weighed by opacity, share of the fur depth.
    mean: f32,
    // Its premultiplied color split among the HEIGHT_NODES heights (PRT only; zero otherwise).
    nodes: array<vec3<f32>, HEIGHT_NODES>,
};

// Lighting at one point, affine in the (premultiplied) texel: lit = albedo × scale + alpha × add.
// The marched shells darken `ambient` and the rest apart (`march_banks`); elsewhere it is zero,
// folded into `scale`.
struct HairLight {
    ambient: vec3<f32>,
    scale: vec3<f32>,
    add: vec3<f32>,
};

// A clip position outside the view volume: a primitive whose corners all go here is dropped.
const CULLED: vec4<f32> = vec4<f32>(2.0, 2.0, 2.0, 1.0);

fn clip_position(p: vec3<f32>) -> vec4<f32> {
    return frame.view_proj * vec4<f32>(p, 1.0);
}

// Unit vector from `p` toward the viewer.
fn view_vector(p: vec3<f32>) -> vec3<f32> {
    return normalize(frame.eye.xyz - p * frame.eye.w);
}

// The surface's curvature from screen derivatives of the normal and position (taken in uniform
// control flow): the larger of the two screen axes', where the normal turns away from the step;
// 0 where flat or concave.
fn surface_curvature(normal: vec3<f32>, position: vec3<f32>) -> f32 {
    return curvature_of_steps(screen_steps(normal, position));
}

// How the normal and the position change from a pixel to the next along the screen's x and y.
struct SurfaceSteps {
    dnx: vec3<f32>,
    dpx: vec3<f32>,
    dny: vec3<f32>,
    dpy: vec3<f32>,
};

// The steps of `normal` and `position` (screen derivatives: uniform control flow).
fn screen_steps(normal: vec3<f32>, position: vec3<f32>) -> SurfaceSteps {
    return SurfaceSteps(dpdx(normal), dpdx(position), dpdy(normal), dpdy(position));
}

// `surface_curvature` from the steps.
fn curvature_of_steps(s: SurfaceSteps) -> f32 {
    let kx = dot(s.dnx, s.dpx) / max(dot(s.dpx, s.dpx), 1e-30);
    let ky = dot(s.dny, s.dpy) / max(dot(s.dpy, s.dpy), 1e-30);
    return max(max(kx, ky), 0.0);
}

// The normal curvature along the tangent direction `d`: `d` written as a mix of the two position
// steps (least squares), the normal's steps mixed alike give how the normal turns along it; 0
// where concave, the axes' larger where the steps span no plane. A torus's tube seen along its
// flat direction, or a crease, curves across the view but not along it.
fn curvature_along(s: SurfaceSteps, d: vec3<f32>) -> f32 {
    let g = vec3<f32>(dot(s.dpx, s.dpx), dot(s.dpx, s.dpy), dot(s.dpy, s.dpy));
    let det = g.x * g.z - g.y * g.y;
    let dd = dot(d, d);
    if (!(det > 1e-12 * g.x * g.z && dd > 0.0)) {
        return curvature_of_steps(s);
    }
    let r = vec2<f32>(dot(s.dpx, d), dot(s.dpy, d));
    let a = (g.z * r.x - g.y * r.y) / det;
    let b = (g.x * r.y - g.y * r.x) / det;
    return max(dot(a * s.dnx + b * s.dny, d) / dd, 0.0);
}

// The curvature along the edge from `p0` (normal `n0`) to `p1` (`n1`): how fast the normal turns
// per unit of it; 0 where flat or concave.
fn edge_curvature(p0: vec3<f32>, n0: vec3<f32>, p1: vec3<f32>, n1: vec3<f32>) -> f32 {
    let edge = p1 - p0;
    return max(dot(n1 - n0, edge) / max(dot(edge, edge), 1e-30), 0.0);
}

// Angle, radians, over which the hot spot fades (e^−1 at this angle between light and view):
// the reference's strands lose their lead over their own density volume (which has no hot
// spot) between 0 and 20° and keep it beyond (docs/accuracy.md).
const HOT_SPOT_WIDTH: f32 = 0.35;

// How much of the path from `light` is the view ray's own (Hapke's shadow hiding): 1 when the
// light comes from the eye, fading over HOT_SPOT_WIDTH. Both lighting models clear their fur's
// shadow by it: Banks darkening (`lighting.wgsl`) and the transfer (`prt.wgsl`).
fn shared_path(light: vec3<f32>, view: vec3<f32>) -> f32 {
    let apart = acos(clamp(dot(light, view), -1.0, 1.0));
    return exp(-apart / HOT_SPOT_WIDTH);
}

// The direction hair grows at a vertex: the normal plus the tangential part of the comb vector
// (Lengyel et al. 2001, §3: combing shears the shells and fins by c_v's tangential component).
fn growth(normal: vec3<f32>, comb: vec3<f32>) -> vec3<f32> {
    return normal + comb - normal * dot(normal, comb);
}

fn unit_or(v: vec3<f32>, fallback: vec3<f32>) -> vec3<f32> {
    let len2 = dot(v, v);
    return select(fallback, v * inverseSqrt(len2), len2 > 1e-24);
}

// Squeezes of the fin texture along the edge beyond this many times its squeeze along the height
// are left to alias rather than blurred into the height.
const FIN_ANISOTROPY: f32 = 8.0;

// The fin texel at `uv`, its mip level picked by the texture's footprint along the fur's height
// (up to FIN_ANISOTROPY times finer than the footprint along the edge): a fin near the
// silhouette is squeezed along its edge far more than along its height, and a level picked by
// the larger squeeze blurred its rows together, spilling the opaque roots up to the tips. One
// trilinear read, where the sampler's own anisotropic filtering cost a CPU adapter 2-3 times
// the fins' time.
// `density`: the fin's hairs per unit of its width over the tile's (`spread_out`).
fn fin_texel(uv: vec2<f32>, density: f32) -> vec4<f32> {
    let size = vec2<f32>(textureDimensions(fin_texture));
    let across = length(dpdx(uv) * size);
    let down = length(dpdy(uv) * size);
    let footprint = max(min(across, down), max(across, down) / FIN_ANISOTROPY);
    let texel = textureSampleLevel(fin_texture, fin_sampler, uv, log2(max(footprint, 1e-6)));
    return spread_out(texel, density);
}

// How far the shells' and fins' hair may thin out or crowd (`density_of_growth`): at
// the focus of a hollow tighter than the fur depth the lifted surface has no area at all.
const MIN_SPREAD: f32 = 0.25;

// How a triangle's cross-section grows with height: lifted by `h` times its corners' growth
// vectors (differing by `d1`, `d2` along its edges `e1`, `e2`), it has `1 + a h + b h²` times its
// own area, projected on its own plane; (a, b), 0 for a triangle of no area. The strands stand on
// the same lift (`placement`) and keep their count and width, so at height h they cover
// 1 / (1 + a h + b h²) of the surface that the tile's texel covers: on a sphere of radius R under
// fur of depth d, (R / (R + h d))².
fn triangle_spread(e1: vec3<f32>, e2: vec3<f32>, d1: vec3<f32>, d2: vec3<f32>) -> vec2<f32> {
    let area = cross(e1, e2);
    let norm = dot(area, area);
    if (!(norm > 0.0)) {
        return vec2<f32>(0.0);
    }
    let linear = cross(e1, d2) + cross(d1, e2);
    return vec2<f32>(dot(linear, area), dot(cross(d1, d2), area)) / norm;
}

// `triangle_spread` of a fragment's triangle from the screen steps of its `position`, lifted
// `stand` (share of the fur depth) along the interpolated growth vector `up`: the steps of two
// functions linear over the triangle are its edges' images under one map, whose area cancels.
// Uniform control flow.
fn screen_spread(position: vec3<f32>, up: vec3<f32>, stand: f32) -> vec2<f32> {
    let ux = dpdx(up);
    let uy = dpdy(up);
    return triangle_spread(dpdx(position) - stand * ux, dpdy(position) - stand * uy, ux, uy);
}

// The hair's number per unit area at `height` (share of the fur depth) over the tile's, on a
// triangle of `spread` (`triangle_spread`).
fn hair_density(spread: vec2<f32>, height: f32) -> f32 {
    return density_of_growth(1.0 + height * (spread.x + height * spread.y));
}

// The hair's density where the surface (or a fin's width) holding it has grown `grown` times:
// its inverse, within the bounds. Past a hollow's focus the lifted surface turns over and widens
// again.
fn density_of_growth(grown: f32) -> f32 {
    return 1.0 / clamp(abs(grown), MIN_SPREAD, 1.0 / MIN_SPREAD);
}

// A premultiplied texel of the tile's hair where that hair stands at `density` times the tile's
// number per unit area (or width): the shells and fins are the mesh lifted along diverging
// growth directions, which stretches the tile over more surface at height on a convex skin
// (fewer hairs there, each as thin as at the root) and less in a hollow. Hairs fall at random,
// so the optical depth -ln(1 - a) scales with their number.
fn spread_out(texel: vec4<f32>, density: f32) -> vec4<f32> {
    if (density == 1.0 || texel.a <= 0.0) {
        return texel;
    }
    let a = 1.0 - pow(max(1.0 - texel.a, 1e-7), density);
    return texel * (a / texel.a);
}
