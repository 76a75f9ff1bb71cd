#define_import_path pelt::surface_prt

#import pelt::common::{
    frame, skin_vertices, SKIN_FLOATS, skin_vec3, NO_LAYER, Layers, skin_layers, shell_layers,
    HairLight, growth, body_shadow, unit_or, view_vector, HEIGHT_NODES, Shown, SurfaceSteps,
    triangle_spread,
}
#import pelt::prt::{transfer_radiance, node_radiances, hot_spot, shown_heights}
#import pelt::lighting::shade_skin
#import pelt::surface::{
    SurfaceData, lift, Texels, layer_texels, blended, lone_share, uv_gradients, MarchFrame,
}

// The skin and shells under PRT lighting (prt-shell-fur §2.4). The rotated lighting lives per
// surface vertex in a storage buffer and has too many coefficients to interpolate as vertex
// outputs, so the draw is not indexed: each vertex invocation is one triangle corner, reads the
// triangle's three surface vertices from the index buffer (vertex pulling), and hands them on
// (flat) with a barycentric one-hot; the fragment interpolates the three vertices' lighting.

// The corners read the skin's vertices (`skin_vertices`) through these indices.
@group(1) @binding(3) var<storage, read> surface_indices: array<u32>;
@group(1) @binding(5) var<storage, read> surface_colors: array<vec4<f32>>;
@group(1) @binding(6) var<storage, read> surface_lengths: array<f32>;

struct SurfaceIn {
    @builtin(vertex_index) corner: u32,
};

// What the fragment reads, unpacked from `SurfaceVarying`.
struct SurfaceOut {
    uv: vec2<f32>,
    color: vec4<f32>,
    length: f32,
    // Array layers of the level drawn and the coarser one, level-0 height (see `Layers`).
    layer: u32,
    coarse: u32,
    height: u32,
    ids: vec3<u32>,
    bary: vec3<f32>,
    // The weights as interpolated, unclamped: their screen derivatives are the triangle's
    // (`march_frame`).
    extrapolated: vec3<f32>,
    // The hot spot's share of the lighting at the fragment (`hot_spot`).
    hot: f32,
    // How the triangle grows with height (`triangle_spread`).
    spread: vec2<f32>,
};

// `SurfaceOut` as it crosses from vertex to fragment, in few locations (a CPU adapter sets up
// every output location of every triangle, whatever its width).
struct SurfaceVarying {
    @builtin(position) clip: vec4<f32>,
    // uv, length, hot spot.
    @location(0) uv_length_hot: vec4<f32>,
    @location(1) color: vec4<f32>,
    @location(2) bary: vec3<f32>,
    @location(3) @interpolate(flat) ids: vec3<u32>,
    // Layer drawn, coarser layer, height; the triangle's spread (`packed_spread`).
    @location(4) @interpolate(flat) layers: vec4<u32>,
};

// The barycentric weights are clamped to the triangle for the lighting: a fragment of a triangle
// seen nearly edge on interpolates them far outside it, and the lighting and hot-spot gains
// weighed by them blew up (a pixel of -1200 in a dolly of the benchmark's long-furred sphere).
fn surface_fragment(v: SurfaceVarying) -> SurfaceOut {
    let w = max(v.bary, vec3<f32>(0.0));
    let bary = w / max(w.x + w.y + w.z, 1e-6);
    return SurfaceOut(v.uv_length_hot.xy, v.color, v.uv_length_hot.z, v.layers.x, v.layers.y,
                      v.layers.z, v.ids, bary, v.bary, v.uv_length_hot.w,
                      unpack2x16snorm(v.layers.w) * SPREAD_RANGE);
}

// The largest spread coefficient `packed_spread` keeps.
const SPREAD_RANGE: f32 = 64.0;

// How the triangle of surface vertices `ids` grows with height under its painted lengths
// (`painted`) or the length multiplier 1, packed to two 16-bit fixed-point numbers (half floats
// need a capability a device may lack): a triangle's corners read its three vertices once each,
// where a fragment would read them for every shell.
fn packed_spread(ids: vec3<u32>, painted: bool) -> u32 {
    var p: array<vec3<f32>, 3>;
    var up: array<vec3<f32>, 3>;
    for (var c = 0u; c < 3u; c++) {
        let id = ids[c];
        p[c] = skin_vec3(id, 0u);
        let length = select(1.0, surface_lengths[id], painted);
        up[c] = frame.fur.x * length * growth(skin_vec3(id, 3u), skin_vec3(id, 14u));
    }
    let spread = triangle_spread(p[1] - p[0], p[2] - p[0], up[1] - up[0], up[2] - up[0]);
    // Beyond ±SPREAD_RANGE the density is clamped anyway (`hair_density`); in steps of 0.002.
    return pack2x16snorm(spread / SPREAD_RANGE);
}

// A skin vertex's distances to the open border (`SurfaceVertex::border`).
fn skin_border(v: u32) -> vec2<f32> {
    let b = v * SKIN_FLOATS;
    return vec2<f32>(skin_vertices[b + 17u], skin_vertices[b + 18u]);
}

fn load_surface(v: u32) -> SurfaceData {
    let b = v * SKIN_FLOATS;
    let uv = vec2<f32>(skin_vertices[b + 12u], skin_vertices[b + 13u]);
    return SurfaceData(skin_vec3(v, 0u), skin_vec3(v, 3u), skin_vec3(v, 6u), skin_vec3(v, 9u), uv,
                       skin_vec3(v, 14u), surface_colors[v], surface_lengths[v]);
}

// The corner lifted to level-0 height `stand` (in layers), with its painted length (`painted`)
// or the length multiplier 1.
fn surface_vertex(v: SurfaceIn, layers: Layers, stand: f32, painted: bool) -> SurfaceVarying {
    let first = v.corner - v.corner % 3u;
    let ids = vec3<u32>(surface_indices[first], surface_indices[first + 1u],
                        surface_indices[first + 2u]);
    let d = load_surface(surface_indices[v.corner]);
    let lifted = lift(d, stand, select(1.0, d.length, painted));
    var bary = vec3<f32>(0.0);
    bary[v.corner % 3u] = 1.0;
    return SurfaceVarying(lifted.clip, vec4<f32>(d.uv, d.length, hot_spot(lifted.position)),
                          d.color, bary, ids,
                          vec4<u32>(layers.fine, layers.coarse, layers.height,
                                    packed_spread(ids, painted)));
}

// The skin is a surface at height 0, lit by the transfer of its own layer; its `SkinVarying` is
// `SurfaceVarying` (an alias would not cross into the pass: `skin.wgsl` imports it renamed).
fn skin_vertex(v: SurfaceIn) -> SurfaceVarying {
    return surface_vertex(v, skin_layers(), 0.0, false);
}

fn skin_fragment(v: SurfaceVarying) -> vec3<f32> {
    let s = surface_fragment(v);
    let texels = layer_texels(s.uv, s.layer, s.coarse);
    let furred = shade_surface(s, texels, 1.0, uv_gradients(s.uv), 0.0).rgb;
    if (s.length == 1.0) {
        return furred;
    }
    return painted_skin(bare_skin(blended(texels).rgb * s.color.rgb, s.ids, s.bary), furred,
                        s.length);
}

// The skin of `albedo` between surface vertices `ids` with weights `w` with no fur over it:
// Kajiya–Kay's bald skin (`shade_skin` at length 0, with no terminator band), a Lambertian
// surface lit by the sky's irradiance about its normal over π (`frame.ambient`, which PRT sets
// from its environment too) and by Kd E/π N·L, shadowed by the body. Not the transfer's SH: a
// sun's band-limited clamped cosine overshoots toward the terminator (a half-bald sphere's bald
// side at 1.14 of the reference's under a sun from the eye).
fn bare_skin(albedo: vec3<f32>, ids: vec3<u32>, w: vec3<f32>) -> vec3<f32> {
    let position = skin_between(ids, w, 0u);
    let n = unit_or(skin_between(ids, w, 3u), vec3<f32>(0.0, 0.0, 1.0));
    return shade_skin(albedo, n, view_vector(position), 0.0, 0.0, body_shadow(position, n));
}

// The skin under hair of painted length `l`: the transfer's darkening of the bare surface
// (`furred` over `bare`) to the power l, as Beer–Lambert has it for l times the fur; bare at
// l = 0 (the tile's transfer, baked for length 1, had lit a half-bald sphere's bald side at 0.61
// of the reference's under a sun from the eye, 0.21 under one from the side), the transfer
// itself at l = 1.
fn painted_skin(bare: vec3<f32>, furred: vec3<f32>, l: f32) -> vec3<f32> {
    let through = max(furred, vec3<f32>(0.0)) / max(bare, vec3<f32>(1e-6));
    return bare * pow(max(through, vec3<f32>(1e-8)), vec3<f32>(max(l, 0.0)));
}

// Each level's texel × vertex color, lit by the transfer of its own layer (the two levels'
// layers are lit differently), cross-faded; premultiplied, opacity × texel alpha. A layer with
// no coarser twin fades its color with its alpha (`lone_share`). The hot spot raises
// each by its own layer's factor.
fn shade_surface(s: SurfaceOut, texels: Texels, opacity: f32, grad: vec4<f32>,
                 wrap: f32) -> vec4<f32> {
    let tint = s.color.rgb * opacity;
    let fine = texels.fine.rgb
        * transfer_radiance(s.ids, s.bary, s.uv, s.layer, grad, texels.fine.a, s.hot);
    var rgb = fine;
    if (frame.fin.y > 0.0) {
        var coarse: vec3<f32>;
        if (s.coarse == NO_LAYER) {
            // A lone layer's coarse texel is its own, scaled (`layer_texels`): lit as itself.
            coarse = fine * lone_share(texels.fine.a);
        } else {
            coarse = texels.coarse.rgb
                * transfer_radiance(s.ids, s.bary, s.uv, s.coarse, grad, texels.coarse.a, s.hot);
        }
        rgb = mix(fine, coarse, frame.fin.y);
    }
    return vec4<f32>(rgb * tint, blended(texels).a * opacity);
}

// The triangle's spread, from its corners.
fn surface_spread(s: SurfaceOut, stand: f32) -> vec2<f32> {
    return s.spread;
}

// PRT fades its directional light past each vertex's terminator in `prt_rotate.wgsl`: no band
// here (`wrap` is unused).
fn surface_wrap(s: SurfaceOut) -> f32 {
    return 0.0;
}

// The vec3 at float `offset` of the skin vertices `ids` (pulled, as the vertex shader does),
// interpolated with weights `w`.
fn skin_between(ids: vec3<u32>, w: vec3<f32>, offset: u32) -> vec3<f32> {
    return w.x * skin_vec3(ids.x, offset) + w.y * skin_vec3(ids.y, offset)
        + w.z * skin_vec3(ids.z, offset);
}

// The hull fragment's point, tile frame and curvature for the marched shells (`marched.wgsl`),
// interpolated from the geometry of the triangle's three surface vertices (pulled, as the vertex
// shader does; the fragment stage reads no color or length buffer, within the storage buffer
// limit).
fn march_frame(s: SurfaceOut) -> MarchFrame {
    let lift = frame.fur.x * s.length;
    let height = f32(shell_layers(frame.counts.x - 1u).height) * frame.fur.y;
    // The curvature from the steps of the weights (varyings, which a helper lane extrapolates)
    // over the three vertices: screen derivatives of the pulled values themselves are no
    // triangle's, as a CPU adapter's helper lanes read zeros from storage buffers. They had made a
    // flat patch's hull curve as h / |p|² about the origin (h the hull's height; up to 4.6 per
    // unit), and a third of its long fur marched nothing, the fins showing through.
    let wx = dpdx(s.extrapolated);
    let wy = dpdy(s.extrapolated);
    // Each vertex's position, normal, dP/du, dP/dv and comb, at float offsets 0, 3, 6, 9 and 14.
    var position = vec3<f32>(0.0);
    var normal = vec3<f32>(0.0);
    var dpdu = vec3<f32>(0.0);
    var dpdv = vec3<f32>(0.0);
    var comb = vec3<f32>(0.0);
    var steps: SurfaceSteps;
    var border = vec2<f32>(0.0);
    var border_steps = vec4<f32>(0.0);
    var corners: array<vec3<f32>, 3>;
    var ups: array<vec3<f32>, 3>;
    for (var c = 0u; c < 3u; c++) {
        let id = s.ids[c];
        let w = s.bary[c];
        let p = skin_vec3(id, 0u);
        let n = skin_vec3(id, 3u);
        let k = skin_vec3(id, 14u);
        position += w * p;
        normal += w * n;
        dpdu += w * skin_vec3(id, 6u);
        dpdv += w * skin_vec3(id, 9u);
        comb += w * k;
        corners[c] = p;
        ups[c] = lift * growth(n, k);
        let lifted = p + height * ups[c];
        steps.dnx += wx[c] * n;
        steps.dpx += wx[c] * lifted;
        steps.dny += wy[c] * n;
        steps.dpy += wy[c] * lifted;
        let b = skin_border(id);
        border += w * b;
        border_steps += vec4<f32>(wx[c] * b, wy[c] * b);
    }
    let up = lift * growth(normal, comb);
    // Under the interpolated painted length: the fragment stage reads no length buffer.
    let spread = triangle_spread(corners[1] - corners[0], corners[2] - corners[0],
                                 ups[1] - ups[0], ups[2] - ups[0]);
    return MarchFrame(position + height * up, normal, dpdu, dpdv, up, steps, border, border_steps,
                      spread);
}

// The marched composite's light: each of its color's height nodes (`heights.nodes`) lit by the
// hair's mean radiance there (raised by its hot spot, as the instanced shells raise each layer),
// as a factor on the composite's color. The color goes with the height (the tips' color is not
// the roots'), and so does the light: a composite's color lit at its mean height ± their spread
// missed that and left the march 6% darker than the instanced shells under side and top suns
// (0.94 of them on the short-furred sphere at 1024², where both read level 0); by node, within
// 0.6%. The texel's own transfer at the layer where the composite passes half opacity is no fair
// sample of the layers' texels (7.6% from the instanced shells, median over the canonical
// scenes). The virtual planes are lit alike.
fn march_light(s: SurfaceOut, f: MarchFrame, uv: vec2<f32>, layers: Layers, alpha: f32,
               grad: vec4<f32>, heights: Shown) -> HairLight {
    let light = node_radiances(s.ids, s.bary, hot_spot(f.position));
    var nodes = heights.nodes;
    var lit = vec3<f32>(0.0);
    var color = vec3<f32>(0.0);
    for (var k = 0u; k < HEIGHT_NODES; k++) {
        lit += nodes[k] * light[k];
        color += nodes[k];
    }
    return HairLight(vec3<f32>(0.0), lit / max(color, vec3<f32>(1e-6)), vec3<f32>(0.0));
}

// The heights the march composites a layer of `layers` at (`march.wgsl` `composite`), that of the
// level drawn or (`coarse`) of its coarser twin, read at mip level `mip`: those of the hair its
// texels show (`shown_heights`).
fn march_heights(layers: Layers, coarse: bool, mip: f32) -> vec2<f32> {
    if (coarse && layers.coarse != NO_LAYER) {
        return shown_heights(layers.coarse, layers.height, mip);
    }
    return shown_heights(layers.fine, layers.height, mip);
}

// The virtual planes' lighting: the march's (their slices hold no transfer of their own either:
// a slice is a slab seen from the side, not a shell texel).
fn plane_light(s: SurfaceOut, f: MarchFrame, uv: vec2<f32>, layers: Layers, grad: vec4<f32>,
               heights: Shown) -> HairLight {
    return march_light(s, f, uv, layers, 1.0, grad, heights);
}

// The transfer holds the hair's self-shadowing: no Banks darkening on top.
fn march_banks(s: SurfaceOut, f: MarchFrame) -> vec2<f32> {
    return vec2<f32>(0.0);
}
