// Pass (d), the guard hairs (hybrid-fur-volume-and-strands §3): every strand a tapered ribbon
// facing the eye, its corners pulled from storage (no vertex buffers and no geometry shader,
// which Metal and WebGPU lack). One triangle strip holds every strand: a strand's block is its
// first corner again, corner `2 j + side` of each drawn point `j`, and its last corner again,
// so that the triangles joining two strands have no area; instance `k` is band `k`. Each strand's points stand in the frame of the
// surface at its root (`guard_strands.rs`), rebuilt here from the skin's vertices, so a pose
// carries them. Band `k` of the frame's strand order (`strands.rs`) keeps the fragments
// between its heights, so each band lands among the shells where it stands. The lighting model
// (`strand_kk.wgsl`, `strand_prt.wgsl`, `light_model.wgsl` states its interface) shades.

#import pelt::common::{
    frame, shell_layers, CULLED, clip_position, view_vector, unit_or, skin_vec3, edge_curvature,
}
#import pelt::lighting::terminator_wrap
#import pelt::light_model::StrandOut
#ifdef PRT
#import pelt::strand_prt as model
#else
#import pelt::strand_kk as model
#endif

struct GuardStrand {
    // The root triangle's skin vertices; the strand's first point.
    corners: vec4<u32>,
    // The root's barycentric weights; the length multiplier there.
    shape: vec4<f32>,
    // Linear albedo at the root; the strand's LOD rank in [0, 1).
    root_color: vec4<f32>,
    // Linear albedo at the tip; the strand's point count.
    tip_color: vec4<f32>,
};

@group(2) @binding(0) var<storage, read> guard_strands: array<GuardStrand>;
// Per point: its place in the root frame (t, b, n), object units, and its radius.
@group(2) @binding(1) var<storage, read> guard_points: array<vec4<f32>>;
// Per strand, the surface's frame at its root in the current pose: origin, t, n (`w` unused).
@group(2) @binding(2) var<storage, read> guard_frames: array<vec4<f32>>;

// A unit vector perpendicular to `n`.
fn perpendicular(n: vec3<f32>) -> vec3<f32> {
    let axis = select(vec3<f32>(0.0, 1.0, 0.0), vec3<f32>(1.0, 0.0, 0.0), abs(n.x) < 0.9);
    return normalize(cross(n, axis));
}

struct RootFrame {
    origin: vec3<f32>,
    t: vec3<f32>,
    b: vec3<f32>,
    n: vec3<f32>,
};

// The frame of the (posed) surface at strand `i`'s root (`guard_strands::root_frames`).
fn root_frame(i: u32) -> RootFrame {
    let t = guard_frames[3u * i + 1u].xyz;
    let n = guard_frames[3u * i + 2u].xyz;
    return RootFrame(guard_frames[3u * i].xyz, t, cross(n, t), n);
}

// Point `k` of strand `s`: object position and radius.
fn strand_point(f: RootFrame, s: GuardStrand, k: u32) -> vec4<f32> {
    let p = guard_points[s.corners.w + k];
    return vec4<f32>(f.origin + p.x * f.t + p.y * f.b + p.z * f.n, p.w);
}

// Height of point `k` as a share of the fur depth at the root.
fn strand_height(s: GuardStrand, k: u32) -> f32 {
    return guard_points[s.corners.w + k].z / max(frame.fur.x * s.shape.w, 1e-20);
}

const FAR_HEIGHT: f32 = 3.0e38;
// Flags of `frame.strand_counts.z`: one band holds every fragment; stochastic coverage.
const WHOLE: u32 = 1u;
const STOCHASTIC: u32 = 2u;

// Height share of shell instance `i`.
fn shell_height(i: u32) -> f32 {
    return f32(shell_layers(i).height) * frame.fur.y;
}

// Band `k`'s heights: drawn before shell c_k = round(k S / n) of the S drawn, it holds the
// fragments from the shell below c_k to the shell below c_(k+1); band n, after every shell, the
// rest.
fn band_range(k: u32) -> vec2<f32> {
    let n = frame.strand_counts.x;
    let shells = frame.counts.x;
    if ((frame.strand_counts.z & WHOLE) != 0u || shells == 0u) {
        return vec2<f32>(-FAR_HEIGHT, FAR_HEIGHT);
    }
    let start = (k * shells * 2u + n) / (2u * n);
    let end = ((k + 1u) * shells * 2u + n) / (2u * n);
    let low = select(shell_height(start - 1u), -FAR_HEIGHT, start == 0u);
    let below_end = select(shell_height(end - 1u), -FAR_HEIGHT, end == 0u);
    let high = select(below_end, FAR_HEIGHT, k >= n);
    return vec2<f32>(low, high);
}

// Pixels across `radius` at `p`, seen along `side`.
fn pixels_across(p: vec3<f32>, side: vec3<f32>, radius: f32) -> f32 {
    let a = clip_position(p);
    let b = clip_position(p + side * radius);
    let d = (b.xy / b.w - a.xy / a.w) * frame.strand.xy * 0.5;
    return length(d);
}

// The terminator band's width at a strand's root: its triangle's curvature (the largest of its
// edges') under the fur there.
fn root_wrap(s: GuardStrand) -> f32 {
    var p: array<vec3<f32>, 3>;
    var n: array<vec3<f32>, 3>;
    for (var i = 0u; i < 3u; i++) {
        p[i] = skin_vec3(s.corners[i], 0u);
        n[i] = skin_vec3(s.corners[i], 3u);
    }
    let k = max(edge_curvature(p[0], n[0], p[1], n[1]),
                max(edge_curvature(p[1], n[1], p[2], n[2]), edge_curvature(p[2], n[2], p[0], n[0])));
    return terminator_wrap(k, frame.fur.x * s.shape.w);
}

// Point index of drawn point `j` of `drawn` segments over a strand of `count` points: every
// k-th point, the root and the tip always.
fn drawn_point(j: u32, drawn: u32, count: u32) -> u32 {
    return (j * (count - 1u) + drawn / 2u) / drawn;
}

@vertex
fn vs_main(@builtin(vertex_index) vertex: u32, @builtin(instance_index) band: u32) -> StrandOut {
    var out: StrandOut;
    out.clip = CULLED;
    let segments = max(frame.strand_counts.y, 1u);
    let block = 2u * segments + 4u;
    let strand = vertex / block;
    let corner = clamp(vertex - strand * block, 1u, block - 2u) - 1u;
    let s = guard_strands[strand];
    let count = u32(s.tip_color.w);
    let drawn = min(segments, count - 1u);
    // Strand LOD, first, so that a dropped strand costs little: a strand thinner than
    // `frame.strand.z` pixels (measured across the view at its root) is kept with probability
    // its width / that, drawn that wide: fewer, wider strands with the same coverage.
    var widen = 1.0;
    if (frame.strand.z > 0.0) {
        let root = guard_frames[3u * strand].xyz;
        let across = 2.0 * pixels_across(root, perpendicular(view_vector(root)),
                                         guard_points[s.corners.w].w);
        let keep = clamp(across / frame.strand.z, frame.strand.w, 1.0);
        if (s.root_color.w >= keep) {
            return out;
        }
        widen = 1.0 / keep;
    }
    // A strand wholly outside the band is dropped (its points' heights bound it).
    let range = band_range(band);
    if ((frame.strand_counts.z & WHOLE) == 0u) {
        var low = FAR_HEIGHT;
        var high = -FAR_HEIGHT;
        for (var j = 0u; j <= drawn; j++) {
            let h = strand_height(s, drawn_point(j, drawn, count));
            low = min(low, h);
            high = max(high, h);
        }
        if (high < range.x || low >= range.y) {
            return out;
        }
    }
    let f = root_frame(strand);
    // Past the strand's last drawn point (a strand of fewer segments than drawn), the strip
    // repeats it: triangles of no area.
    let j = min(corner / 2u, drawn);
    let side_sign = select(-1.0, 1.0, (corner & 1u) == 1u);
    let k = drawn_point(j, drawn, count);
    let p = strand_point(f, s, k);
    let before = strand_point(f, s, drawn_point(max(j, 1u) - 1u, drawn, count)).xyz;
    let after = strand_point(f, s, drawn_point(min(j + 1u, drawn), drawn, count)).xyz;
    let tangent = unit_or(after - before, f.n);
    let view = view_vector(p.xyz);
    let side = unit_or(cross(tangent, view), f.t);
    // A ribbon under a pixel wide is drawn a pixel wide, its opacity its coverage.
    let radius = p.w * widen;
    let half_pixels = pixels_across(p.xyz, side, radius);
    let coverage = clamp(2.0 * half_pixels, 0.0, 1.0);
    let drawn_radius = radius * max(1.0, 0.5 / max(half_pixels, 1e-6));
    let position = p.xyz + side * (side_sign * drawn_radius);
    let along = f32(k) / f32(count - 1u);
    let albedo = mix(s.root_color.rgb, s.tip_color.rgb, along);
    out.clip = clip_position(position);
    out.color = vec4<f32>(albedo * coverage, coverage);
    out.tangent_height = vec4<f32>(tangent, strand_height(s, k));
    out.normal = f.n;
    out.position = position;
    out.band = range;
    out.corners = s.corners.xyz;
    out.weights = s.shape.xyz;
    out.strand = strand;
    out.wrap_length = vec2<f32>(root_wrap(s), s.shape.w);
    return out;
}

// A hash of a pixel and a strand, uniform in [0, 1) (the PCG output function).
fn coverage_draw(pixel: vec2<u32>, strand: u32) -> f32 {
    var h = pixel.x * 747796405u + pixel.y * 2891336453u + strand * 277803737u + 2654435769u;
    h = ((h >> ((h >> 28u) + 4u)) ^ h) * 277803737u;
    h = (h >> 22u) ^ h;
    return f32(h >> 8u) * (1.0 / 16777216.0);
}

@fragment
fn fs_main(v: StrandOut) -> @location(0) vec4<f32> {
    let height = v.tangent_height.w;
    if (height < v.band.x || height >= v.band.y) {
        discard;
    }
    var s = v;
    // Stochastic transparency: the coverage kept as the chance the fragment is drawn at all,
    // opaque, so the depth buffer orders it exactly.
    if ((frame.strand_counts.z & STOCHASTIC) != 0u) {
        let c = v.color.a;
        if (coverage_draw(vec2<u32>(v.clip.xy), v.strand) >= c) {
            discard;
        }
        s.color = vec4<f32>(v.color.rgb / max(c, 1e-6), 1.0);
    }
    return model::shade_strand(s, unit_or(v.tangent_height.xyz, v.normal), clamp(height, 0.0, 1.0));
}
