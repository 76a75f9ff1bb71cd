// Pass (c), virtual planes (raycast-fur-virtual-planes §3, after Habel et al.'s grass): the hull
// (the outermost shell) traces each fragment's view ray down through two families of planes
// standing on the surface, `N` across the tile's u and `N` across its v, each textured with
// its own slice of the hair (`volume/slices.rs`), composited front to back in the order the ray
// crosses them, until the skin (§3.1). The planes lean with the hair (§3.6): the ray is traced
// in the tile sheared by the hair's mean slant, in which the slices were cut. Seen head-on a ray
// crosses few planes and the grid shows (§3.5), so a horizontal slice of the volume, the
// half-z plane, stands at the paper's dynamic depth h = 0.9 (1 − N·V) + 0.1 below the top of
// the fur, faded in by (N·V)². The loop limit caps the planes a ray crosses (§4.1).
//
// A slice holds a slab 1/N of the tile deep seen square-on; the ray runs through it obliquely
// and also crosses the other family's planes, so each crossing's opacity is raised to the ray's
// horizontal run to the next crossing, in slab depths: the hair a ray passes is counted once
// whatever its heading (the paper's planes double it on the diagonal). Above a convex skin the
// hair thins out as the shells' does (`hair_density`).

#import pelt::common::{
    frame, shell_texture, tile_sampler, fin_sampler, NO_LAYER, Layers, shell_layers, clip_position,
    view_vector, unit_or, hair_density, spread_out,
}
#import pelt::surface::MarchFrame
#import pelt::march::{
    OPAQUE, Ray, ray_length, Marched, empty_march, composite, shown, lit, footprint_lod,
    hull_fragment,
}
#ifdef PRT
#import pelt::surface_prt as model
#else
#import pelt::surface_kk as model
#endif

@group(0) @binding(7) var plane_texture: texture_2d_array<f32>;

// Most slab depths one crossing may stand for (a ray nearly along a plane).
const MAX_RUN_SLABS: f32 = 64.0;
// The most opacity a slice's texel stands for per slab depth: one 8-bit step below opaque.
const MAX_SLICE_ALPHA: f32 = 254.0 / 255.0;

@vertex
fn vs_main(v: model::SurfaceIn) -> model::SurfaceVarying {
    let hull = shell_layers(frame.counts.x - 1u);
    return model::surface_vertex(v, hull, f32(hull.height), true);
}

// Height above the skin, level-0 layers, after ray length `t` from the hull at height `top`.
fn ray_height(r: Ray, top: f32, t: f32) -> f32 {
    return clamp(top - r.fall * t + r.bend * t * t, 0.0, top);
}

// The slice texel (premultiplied) of array layer `layer` at `along` (tile units across the
// plane) and `height` (level-0 layers), its opacity raised to `run` slab depths.
fn slice_texel(layer: u32, along: f32, height: f32, run: f32, lod: f32) -> vec4<f32> {
    let z = height * frame.fur.y;
    let texel = textureSampleLevel(plane_texture, fin_sampler, vec2<f32>(along, 1.0 - z), layer, lod);
    if (texel.a <= 0.0) {
        return vec4<f32>(0.0);
    }
    // An 8-bit slice saturates at full opacity where its slab's hair overlaps; capped a step
    // below it, a short run through the slab stays partly clear.
    let alpha = 1.0 - pow(1.0 - min(texel.a, MAX_SLICE_ALPHA), clamp(run, 0.0, MAX_RUN_SLABS));
    return texel * (alpha / texel.a);
}

// The slices' mip level. Their width spans a tile, as the shell texture's does, but their
// height the fur depth, which near the silhouette covers far fewer pixels than a tile's width
// is squeezed into: a level chosen by the width alone there averaged the dense roots up into
// the sparse tips, and the fringe went opaque. So the level follows the fur's height in pixels,
// at most 3 levels (8×) finer than the width asks for (as the fin texture's does), and two
// levels finer than the pixel: opacity averaged over a footprint and then composited through a
// run of planes overstates the footprint's coverage, which a sharper, noisier read does not.
fn slice_lod(f: MarchFrame, grad: vec4<f32>, top: f32) -> f32 {
    let size = vec2<f32>(textureDimensions(plane_texture).xy);
    let along = footprint_lod(grad, size.x);
    let a = clip_position(f.position);
    let b = clip_position(f.position - f.up * (top * frame.fur.y));
    let pixels = length((a.xy / a.w - b.xy / b.w) * 0.5 * frame.strand.xy);
    let rows = size.y * top * frame.fur.y / max(pixels, 1e-6);
    let height = log2(max(rows, 1.0));
    return min(along, max(height - 2.0, along - 3.0));
}

// Next crossing of a plane family along one axis: ray length to it, from cell `cell` of
// position `q` moving `rate` (in plane spacings per unit of ray).
fn first_crossing(q: f32, cell: f32, rate: f32) -> f32 {
    if (rate > 0.0) {
        return (cell + 1.0 - q) / rate;
    }
    if (rate < 0.0) {
        return (cell - q) / rate;
    }
    return 1e30;
}

fn trace(s: model::SurfaceOut, f: MarchFrame, ray: Ray, grad: vec4<f32>) -> Marched {
    let n = frame.planes.x;
    let count = u32(n);
    let tilt = frame.planes.zw;
    let hull = shell_layers(frame.counts.x - 1u);
    let top = f32(hull.height);
    var out = empty_march(hull, s.uv);
    // Where the ray meets the skin; at the limb, where it never does, where it leaves the fur.
    var end = ray_length(ray, top);
    if (end < 0.0) {
        end = select(0.0, ray.fall / ray.bend, ray.bend > 0.0 && ray.fall > 0.0);
    }
    // Or where it passes the mesh's open border, where the hair ends.
    end = min(end, ray.border);
    // The sheared tile, in plane spacings: q = (uv − tilt · z) N, linear in the ray length.
    let fall_z = ray.fall * frame.fur.y;
    let q0 = (s.uv - tilt * (top * frame.fur.y)) * n;
    let rate = (ray.uv_rate + tilt * fall_z) * n;
    var cell = floor(q0);
    let step = vec2<f32>(select(-1.0, 1.0, rate.x >= 0.0), select(-1.0, 1.0, rate.y >= 0.0));
    let delta = vec2<f32>(1.0 / max(abs(rate.x), 1e-30), 1.0 / max(abs(rate.y), 1e-30));
    var next = vec2<f32>(first_crossing(q0.x, cell.x, rate.x), first_crossing(q0.y, cell.y, rate.y));
    // Slab depths run per unit of ray.
    let slabs_per_length = length(rate);
    let lod = slice_lod(f, grad, top);
    let half_z_lod = footprint_lod(grad, f32(textureDimensions(shell_texture).x));
    // The half-z plane (§3.5).
    let nv = clamp(dot(unit_or(f.normal, vec3<f32>(0.0, 0.0, 1.0)), view_vector(f.position)), 0.0, 1.0);
    let half_z_drop = (0.9 * (1.0 - nv) + 0.1) * top;
    var half_z = ray_length(ray, half_z_drop);
    if (half_z < 0.0 || half_z > end || nv <= 0.0) {
        half_z = 1e30;
    }
    var crossings = 0u;
    loop {
        if (out.color.a >= OPAQUE) {
            break;
        }
        let across_u = next.x <= next.y;
        let t = min(next.x, next.y);
        // The half-z plane, where the ray passes it before this crossing.
        if (half_z <= t) {
            let uv = s.uv + ray.uv_rate * half_z;
            let height = ray_height(ray, top, half_z);
            let layer = u32(round(height));
            let sampled = textureSampleLevel(shell_texture, tile_sampler, uv, layer, half_z_lod);
            let texel = spread_out(sampled, hair_density(f.spread, height * frame.fur.y)) * (nv * nv);
            if (texel.a * s.color.a >= frame.fur.w) {
                out = composite(out, texel * s.color.a, Layers(layer, layer, NO_LAYER), uv, texel.a,
                                vec2<f32>(height, height * height));
            }
            half_z = 1e30;
            continue;
        }
        if (t >= end || crossings >= u32(frame.planes.y)) {
            break;
        }
        crossings += 1u;
        // Step into the next cell; the slab entered is that cell's.
        var layer: u32;
        var along: f32;
        let q = q0 + rate * t;
        if (across_u) {
            cell.x += step.x;
            next.x += delta.x;
            layer = u32(cell.x - n * floor(cell.x / n)) % count;
            along = q.y / n;
        } else {
            cell.y += step.y;
            next.y += delta.y;
            layer = count + u32(cell.y - n * floor(cell.y / n)) % count;
            along = q.x / n;
        }
        let run = (min(min(next.x, next.y), end) - t) * slabs_per_length;
        let height = ray_height(ray, top, t);
        let density = hair_density(f.spread, height * frame.fur.y);
        let texel = spread_out(slice_texel(layer, along, height, run, lod), density) * s.color.a;
        if (texel.a < frame.fur.w) {
            continue;
        }
        let uv = s.uv + ray.uv_rate * t;
        let shown = u32(round(height));
        out = composite(out, texel, Layers(shown, shown, NO_LAYER), uv, texel.a,
                        vec2<f32>(height, height * height));
    }
    return out;
}

@fragment
fn fs_main(v: model::SurfaceVarying) -> @location(0) vec4<f32> {
    let h = hull_fragment(v);
    // Bald faces draw no fur.
    if (h.s.length <= 0.0) {
        discard;
    }
    let m = trace(h.s, h.f, h.ray, h.grad);
    if (m.color.a <= 0.0) {
        discard;
    }
    return lit(h.s, h.f, m, model::plane_light(h.s, h.f, m.uv, m.shown, h.grad, shown(m)));
}
