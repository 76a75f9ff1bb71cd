// Pass (b), the fins (Lengyel et al. 2001, §2.3): one quad per mesh edge standing along the
// growth direction, faded by max(0, 2|p| - 1) with p = fin normal · view direction, so that only
// fins near the silhouette (also just over the horizon) show. Depth tested, not written. The
// lighting model (`fin_kk.wgsl` or `fin_prt.wgsl`, `light_model.wgsl` states its interface)
// defines what reaches the fragment (`FinOut`, made by `fin_vertex`) and its color
// (`fin_fragment`).

#import pelt::common::{
    frame, skin_vec3, CULLED, clip_position, view_vector, growth, edge_curvature,
    density_of_growth,
}
#import pelt::lighting::terminator_wrap
#import pelt::light_model::{FinIn, FinCorner}
#ifdef PRT
#import pelt::fin_prt as model
#else
#import pelt::fin_kk as model
#endif

@vertex
fn vs_main(v: FinIn) -> model::FinOut {
    let p0 = skin_vec3(v.ends.x, 0u);
    let p1 = skin_vec3(v.ends.y, 0u);
    let n0 = skin_vec3(v.ends.x, 3u);
    let n1 = skin_vec3(v.ends.y, 3u);
    // The fin plane of `mesh::fin_plane`: the ends' summed normals × the edge; none (the fin
    // dropped) where that has no direction.
    let edge = p1 - p0;
    let plane = cross(n0 + n1, edge);
    let span = length(plane);
    let fin_normal = select(vec3<f32>(0.0), plane / span, span > 1e-9 * length(edge));
    // p at the edge's midpoint: all four corners agree, so a faded-out fin is dropped whole.
    let p = dot(fin_normal, view_vector(0.5 * (p0 + p1)));
    let fade = max(0.0, 2.0 * abs(p) - 1.0) * frame.fin.x;
    let second = v.along > 0.5;
    let normal = select(n0, n1, second);
    let end = select(v.ends.x, v.ends.y, second);
    let g = growth(normal, skin_vec3(end, 14u));
    // uv.y is 0 at the top of the fur (the fin texture's first row) and 1 at the skin.
    let position = select(p0, p1, second) + (1.0 - v.uv.y) * frame.fur.x * v.length * g;
    let clip = select(CULLED, clip_position(position), fade > 0.0);
    let wrap = terminator_wrap(edge_curvature(p0, n0, p1, n1), frame.fur.x * v.length);
    let lift = frame.fur.x * max(v.length, 0.0) * (growth(n1, skin_vec3(v.ends.y, 14u))
                                                    - growth(n0, skin_vec3(v.ends.x, 14u)));
    let density = fin_density(edge, lift, 1.0 - v.uv.y);
    return model::fin_vertex(v, FinCorner(clip, position, normal, g, skin_vec3(end, 6u),
                                          skin_vec3(end, 9u), fade * v.color.a, density, wrap));
}

// The hair's number per unit of the fin's width at `height` (share of the fur depth) over the
// tile's: the edge `edge` lifted by `height × lift` (the ends' growth vectors' difference) is
// that much longer along itself, and the hairs it shows stand that much farther apart (as thin
// as at the root). Linear across the fin quad, as the width is.
fn fin_density(edge: vec3<f32>, lift: vec3<f32>, height: f32) -> f32 {
    let e2 = dot(edge, edge);
    return density_of_growth(select(1.0, 1.0 + height * dot(lift, edge) / e2, e2 > 0.0));
}

@fragment
fn fs_main(f: model::FinOut) -> @location(0) vec4<f32> {
    let c = model::fin_fragment(f);
    // A coarser geometric level stands its fins `spacing` times as far apart: 1/spacing as many
    // cross any stretch of surface, so each must carry the opacity of `spacing` fins of the full
    // mesh, its color kept per unit of opacity. Where the full mesh's fins fall at random along
    // a ray (Poisson, k on average), its transmittance is E[(1 - a)^N] = exp(-k a), and a coarse
    // level's, exp(-(k / spacing) a'), matches it for a' = spacing × a: linear, up to opaque.
    // (Compounding instead, 1 - (1 - a)^spacing, holds only for fins stacked one behind another
    // on every ray; seen across the surface, where they stand side by side, it let a coarse
    // level's fins fall several percent short of the full mesh's.)
    let spacing = frame.fin.z;
    if (spacing == 1.0 || c.a <= 0.0) {
        return c;
    }
    return c * min(spacing, 1.0 / c.a);
}
