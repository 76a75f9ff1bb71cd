#define_import_path pelt::surface

#import pelt::common::{frame, shell_texture, tile_sampler, NO_LAYER, clip_position, growth,
                     SurfaceSteps}

// What the skin and the shells share (Lengyel et al. 2001, §2.3): both draw the mesh textured by
// a layer of the shell texture; the shells lift it off the skin. The lighting model's module
// (`surface_kk.wgsl` or `surface_prt.wgsl`, `light_model.wgsl` states its interface) defines how
// a vertex is read (`SurfaceIn`, `surface_vertex`), what reaches the fragment (`SurfaceOut`) and
// `shade_surface`.

// A vertex of the skin and shells, however the pass reads it.
struct SurfaceData {
    position: vec3<f32>,
    normal: vec3<f32>,
    dpdu: vec3<f32>,
    dpdv: vec3<f32>,
    uv: vec2<f32>,
    comb: vec3<f32>,
    color: vec4<f32>,
    length: f32,
};

// A vertex lifted to its layer.
struct Lifted {
    clip: vec4<f32>,
    position: vec3<f32>,
    // d(position) / d(tile height): where the tile's up axis points, in object units.
    up: vec3<f32>,
};

// Level-0 height `height` (in layers) sits at `height × spacing` of the fur depth × `length`
// along the growth direction.
fn lift(d: SurfaceData, height: f32, length: f32) -> Lifted {
    let up = frame.fur.x * length * growth(d.normal, d.comb);
    let p = d.position + height * frame.fur.y * up;
    return Lifted(clip_position(p), p, up);
}

// The shell texels (premultiplied) of the level drawn and of the next coarser one (zero when the
// layer has none or no cross-fade runs).
struct Texels {
    fine: vec4<f32>,
    coarse: vec4<f32>,
};

// The texels at `uv` of array layers `fine` and `coarse`, with implicit derivatives. A lone
// layer's (`coarse` NO_LAYER) coarse texel is its own scaled by `lone_share`.
fn layer_texels(uv: vec2<f32>, fine: u32, coarse: u32) -> Texels {
    let texel = textureSample(shell_texture, tile_sampler, uv, fine);
    var faded = vec4<f32>(0.0);
    // The blend is uniform over the frame, so the branch keeps implicit derivatives valid.
    if (frame.fin.y > 0.0) {
        let last = textureNumLayers(shell_texture) - 1u;
        let sampled = textureSample(shell_texture, tile_sampler, uv, min(coarse, last));
        faded = select(sampled, texel * lone_share(texel.a), coarse == NO_LAYER);
    }
    return Texels(texel, faded);
}

// What a lone shell's texel of opacity `alpha` is scaled by toward the coarser level, so that
// mid-fade it shows `(1 − τ) / (1 − τ alpha)` of itself: then it and its faded-in twin above
// cover, and show, exactly the coarser group's composite over the same texel at every blend
// `τ` (the twin's `(1 − τ) c₂ + τ (c₂ + (1 − a₂) c₁)` over it), where fading it linearly let
// the pair cover less mid-fade (a flat patch seen at a slant 3–4% brighter halfway from level
// 4 to 5). Nothing when the coarser level is the skin alone: every shell fades into it.
fn lone_share(alpha: f32) -> f32 {
    let t = frame.fin.y;
    if (frame.lod.w <= 1u) {
        return 0.0;
    }
    return alpha * (1.0 - t) / max(1.0 - t * alpha, 1e-6);
}

// The cross-faded texel.
fn blended(t: Texels) -> vec4<f32> {
    return mix(t.fine, t.coarse, frame.fin.y);
}

// Screen derivatives of the tile UV (dx, dy), taken where control flow is still uniform (before
// a discard) for lookups made after it.
fn uv_gradients(uv: vec2<f32>) -> vec4<f32> {
    return vec4<f32>(dpdx(uv), dpdy(uv));
}

// A point of the hull of the marched shells and its tile frame: `up` is d(position) / d(tile
// height) as in `Lifted`.
struct MarchFrame {
    position: vec3<f32>,
    normal: vec3<f32>,
    dpdu: vec3<f32>,
    dpdv: vec3<f32>,
    up: vec3<f32>,
    // How the surface turns there (`curvature_of_steps`, `curvature_along`).
    steps: SurfaceSteps,
    // Tile units to the open border, to the nearest edge and to the nearest running another way
    // (`SurfaceVertex::border`), and their screen steps: d/dx of both (xy), d/dy (zw).
    border: vec2<f32>,
    border_steps: vec4<f32>,
    // How the hull's triangle grows with height (`triangle_spread`): the hair thins out above it.
    spread: vec2<f32>,
};
