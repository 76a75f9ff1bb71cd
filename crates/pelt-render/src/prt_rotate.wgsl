// Rotates the world lighting (real SH, RGB) into every surface vertex's tile frame for PRT
// (prt-shell-fur §2.4: the transfer was baked in the tile frame, x along the tile's u, y along
// v, z up). The frame is made orthonormal: z the vertex normal, x the tangential part of dP/du,
// y = z × x, mirrored when dP/dv points the other way (a mirrored patch).
//
// The rotation r (rows x, y, z: world to tile) is split into Euler angles, r = Rz(α) Ry(β) Rz(γ),
// and Ry(β) = Rx(-90°) Rz(β) Rx(90°): rotations about z only mix the (m, -m) pairs of a band,
// and the one fixed matrix D(Rx(90°)) (computed once on the CPU by the Ivanic-Ruedenberg
// recurrence, its transpose giving Rx(-90°)) does the rest. That costs two dense products per
// band instead of building each vertex's band matrices.
//
// The directional light is rotated apart, dimmed by the body's shadow over the vertex's fur
// (`column_visibility`), and faded out past the vertex's terminator: the body shadows it there,
// but its few bands spread it some 40° around its direction, which lit the fur a back light
// cannot reach (5× the reference's light). The fade is the Kajiya–Kay
// preview's terminator band (`lighting.wgsl` `terminator_wrap`): hair h tall on a surface
// curving at κ sees √(2hκ) past the terminator in N·L, at most TERMINATOR_WRAP, with κ the
// vertex's from the mesh (pelt-core `scene::curvature`) and h the fur depth (the skin, which reads
// this lighting too, has it faded as under fur of length 1, whatever is painted; so a bald coat
// renders exactly the skin). The light fades over TERMINATOR_WRAP in
// N·L down to that band's edge: on a flat surface it is gone at the horizon, where the fixed
// band had lit the flat patch's fur 10× the reference's under a grazing sun.
//
// Where the light may come from the eye, the pass also weighs the hot spot's gain of the LOD
// composites the frame draws (`write_gains`), which the fragments interpolate (`prt.wgsl`
// `composite_gain`).

#import pelt::hot_spot::{hot_spot_ratio, pack_gain}
#import pelt::body_shadow::map_visibility

// Widest band past the terminator (in N·L), and the width over which the light fades out.
const TERMINATOR_WRAP: f32 = 0.3;

struct Rotation {
    // x: surface vertices, y: order n, z: coefficients n².
    counts: vec4<u32>,
    // xyz: unit direction toward the directional light (object space); w: the fur depth.
    sun_direction: vec4<f32>,
    // x: level-0 layers, y: LOD composites past them, z..w: the composites whose hot-spot gain
    // the frame needs (none while the light cannot come from the eye).
    layers: vec4<u32>,
    // The body's shadow map: object space to the light's clip space, and its `map_visibility`
    // parameters (x 0: no map).
    light_view_proj: mat4x4<f32>,
    shadow: vec4<f32>,
    // The world lighting without the directional light, 1/π folded in; rgb per coefficient.
    light: array<vec4<f32>, 64>,
    // The directional light's cap, alike.
    sun: array<vec4<f32>, 64>,
};

@group(0) @binding(0) var<uniform> params: Rotation;
// SurfaceVertex rows of 19 floats: position, normal, dP/du, dP/dv, uv, comb, border distances.
@group(0) @binding(1) var<storage, read> geometry: array<f32>;
// D(Rx(90°)), bands 0.. one after the other, each (2l+1)² row-major.
@group(0) @binding(2) var<storage, read> x90: array<f32>;
@group(0) @binding(3) var<storage, read_write> rotated: array<vec4<f32>>;
// Per surface vertex, the surface's curvature.
@group(0) @binding(4) var<storage, read> curvature: array<f32>;
// Rows of n² transfer coefficients: level 0's layer means (row = layer), the composites' heights
// (`prt.wgsl` `shown_heights`), then per composite
// member its transfer weighted by what the composite shows of it (`transfer::composite_members`).
@group(0) @binding(5) var<storage, read> means: array<f32>;
// Per composite: its level-0 layers first..end (x, y) and the row of the first's weighted
// transfer (z).
@group(0) @binding(6) var<storage, read> composites: array<vec4<u32>>;
// Per surface vertex and composite, the hot spot's gain (`pack_gain`).
@group(0) @binding(7) var<storage, read_write> gains: array<vec2<u32>>;
@group(0) @binding(8) var shadow_map: texture_depth_2d;
@group(0) @binding(9) var shadow_sampler: sampler_comparison;

const WORKGROUP: u32 = 64u;
const GEOMETRY_FLOATS: u32 = 19u;
// Below this sin β the Euler angles α and γ are ill-defined and only α + γ matters.
const GIMBAL: f32 = 1e-4;

alias Coefficients = array<vec4<f32>, 64>;

fn vec3_at(base: u32) -> vec3<f32> {
    return vec3<f32>(geometry[base], geometry[base + 1u], geometry[base + 2u]);
}

// Coefficients of f(Rz(angle)ᵀ ω): each pair (m, -m) turns by m · angle.
fn rotate_z(c: ptr<function, Coefficients>, angle: f32, order: u32) {
    for (var l = 1u; l < order; l++) {
        let center = l * l + l;
        for (var m = 1u; m <= l; m++) {
            let a = f32(m) * angle;
            let cs = cos(a);
            let sn = sin(a);
            let p = (*c)[center + m];
            let q = (*c)[center - m];
            (*c)[center + m] = p * cs - q * sn;
            (*c)[center - m] = p * sn + q * cs;
        }
    }
}

// dst = D(Rx(90°)) src, or D(Rx(-90°)) src with `inverse` (the transpose).
fn rotate_x90(src: ptr<function, Coefficients>, dst: ptr<function, Coefficients>, order: u32,
              inverse: bool) {
    var offset = 0u;
    for (var l = 0u; l < order; l++) {
        let size = 2u * l + 1u;
        let start = l * l;
        for (var i = 0u; i < size; i++) {
            var acc = vec4<f32>(0.0);
            for (var j = 0u; j < size; j++) {
                let e = select(x90[offset + i * size + j], x90[offset + j * size + i], inverse);
                acc += e * (*src)[start + j];
            }
            (*dst)[start + i] = acc;
        }
        offset += size * size;
    }
}

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>,
        @builtin(num_workgroups) groups: vec3<u32>) {
    let v = id.x + id.y * groups.x * WORKGROUP;
    if (v >= params.counts.x) {
        return;
    }
    let order = params.counts.y;
    let n = params.counts.z;
    let b = v * GEOMETRY_FLOATS;
    let normal = vec3_at(b + 3u);
    let dpdu = vec3_at(b + 6u);
    let dpdv = vec3_at(b + 9u);
    var z = vec3<f32>(0.0, 0.0, 1.0);
    if (dot(normal, normal) > 1e-24) {
        z = normalize(normal);
    }
    var x = dpdu - z * dot(z, dpdu);
    if (dot(x, x) <= 1e-8 * dot(dpdu, dpdu)) {
        // No usable dP/du (zero, or along the normal to within 1e-4): any tangent will do (the
        // pelt is nearly isotropic about the normal).
        x = select(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), abs(z.x) > 0.9);
        x = x - z * dot(z, x);
    }
    x = normalize(x);
    let y = cross(z, x);
    let mirrored = dot(y, dpdv) < 0.0;

    // r = rows (x, y, z) = Rz(α) Ry(β) Rz(γ): third column (cα sβ, sα sβ, cβ), third row
    // (-sβ cγ, sβ sγ, cβ).
    let sb = length(vec2<f32>(x.z, y.z));
    let beta = atan2(sb, z.z);
    var alpha = 0.0;
    var gamma = 0.0;
    if (sb > GIMBAL) {
        alpha = atan2(y.z, x.z);
        gamma = atan2(z.y, -z.x);
    } else {
        // r ≈ Rz(α) (β = 0) or Rz(α) diag(-1, 1, -1) (β = π), with γ = 0.
        alpha = atan2(select(y.x, -y.x, z.z < 0.0), y.y);
    }

    let angles = vec3<f32>(gamma, beta, alpha);
    var c: Coefficients;
    var sun: Coefficients;
    for (var k = 0u; k < n; k++) {
        c[k] = params.light[k];
        sun[k] = params.sun[k];
    }
    rotate_into_frame(&c, angles, order, mirrored);
    let facing = dot(z, params.sun_direction.xyz);
    let band = min(sqrt(2.0 * params.sun_direction.w * curvature[v]), TERMINATOR_WRAP);
    let shown = clamp((facing + band) / TERMINATOR_WRAP, 0.0, 1.0)
        * column_visibility(vec3_at(b), z, params.sun_direction.w);
    if (shown > 0.0) {
        rotate_into_frame(&sun, angles, order, mirrored);
        for (var k = 0u; k < n; k++) {
            c[k] += shown * sun[k];
        }
    }
    for (var k = 0u; k < n; k++) {
        rotated[v * n + k] = c[k];
    }
    if (params.layers.z < params.layers.w) {
        write_gains(v, &c, n);
    }
}

// The share of the directional light the body lets reach the fur over the skin at `position`
// (facing `normal`, under fur `depth` deep): the body's shadow (`map_visibility`) meaned over the
// column's height, as the transfer's rotated lighting serves every layer of it (past a
// terminator the tips see the light while the roots do not).
fn column_visibility(position: vec3<f32>, normal: vec3<f32>, depth: f32) -> f32 {
    if (params.shadow.x == 0.0) {
        return 1.0;
    }
    // The middles of four equal slabs of the column.
    var sum = 0.0;
    for (var i = 0u; i < 4u; i++) {
        let at = position + normal * ((f32(i) + 0.5) * 0.25 * depth);
        sum += map_visibility(shadow_map, shadow_sampler, params.light_view_proj, params.shadow,
                              at, normal);
    }
    return 0.25 * sum;
}

// The lighting `c` dotted with the transfer in row `row` of `means`.
fn radiance(c: ptr<function, Coefficients>, row: u32, n: u32) -> vec3<f32> {
    var sum = vec3<f32>(0.0);
    for (var k = 0u; k < n; k++) {
        sum += (*c)[k].rgb * means[row * n + k];
    }
    return sum;
}

// The hot spot's gain of the composites the frame draws at vertex `v` lit by `c`: all shells
// raise level-0 layer i by its own ratio g_i (`hot_spot_ratio`), so a composite showing light
// R_i of each member gets Σ R_i g_i / Σ R_i (1 where it shows none).
fn write_gains(v: u32, c: ptr<function, Coefficients>, n: u32) {
    let count = params.layers.y;
    let top = radiance(c, params.layers.x - 1u, n);
    for (var j = params.layers.z; j < params.layers.w; j++) {
        let members = composites[j];
        var lifted = vec3<f32>(0.0);
        var shown = vec3<f32>(0.0);
        for (var i = members.x; i < members.y; i++) {
            let r = max(radiance(c, members.z + i - members.x, n), vec3<f32>(0.0));
            lifted += r * hot_spot_ratio(top, radiance(c, i, n));
            shown += r;
        }
        let gain = select(vec3<f32>(1.0), lifted / shown, shown > vec3<f32>(0.0));
        gains[v * count + j] = pack_gain(gain);
    }
}

// `c` turned by r = Rz(α) Ry(β) Rz(γ) (`angles` = γ, β, α), mirrored in y with `mirrored`.
fn rotate_into_frame(c: ptr<function, Coefficients>, angles: vec3<f32>, order: u32,
                     mirrored: bool) {
    var d: Coefficients;
    rotate_z(c, angles.x, order);
    rotate_x90(c, &d, order, false);
    rotate_z(&d, angles.y, order);
    rotate_x90(&d, c, order, true);
    rotate_z(c, angles.z, order);
    // A mirrored frame flips y: the functions odd in y (m < 0) change sign.
    for (var l = 1u; l < order; l++) {
        for (var m = 1u; m <= l; m++) {
            let k = l * l + l - m;
            (*c)[k] = select((*c)[k], -(*c)[k], mirrored);
        }
    }
}
