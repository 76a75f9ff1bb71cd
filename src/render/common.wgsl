// Shared by every fur pass: the frame's uniforms, the scene's textures and small geometry helpers.
// All geometry and lighting are in object space (the mesh's own space).

struct Frame {
    view_proj: mat4x4<f32>,
    // The eye: w = 1 its position (perspective), w = 0 the unit direction toward it (orthographic).
    eye: vec4<f32>,
    // xyz: unit direction toward the light.
    light_direction: vec4<f32>,
    light_color: vec4<f32>,
    ambient: vec4<f32>,
    // Kajiya-Kay Kd, Ks, Pd, Ps.
    kajiya_kay: vec4<f32>,
    // x: fur depth (object units at length 1), y: layer spacing (share of the fur depth),
    // z: Banks self-shadow strength, w: alpha-test threshold of the shells.
    fur: vec4<f32>,
    // x: fin opacity.
    fin: vec4<f32>,
    // x: shells drawn, y: layers of the shell texture.
    counts: vec4<u32>,
    // PRT: x coefficients n², y transfer textures, z array layers per transfer texture,
    // w layers of the volume (the fins' table of layer means).
    prt: vec4<u32>,
};

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var shell_texture: texture_2d_array<f32>;
@group(0) @binding(2) var tangent_texture: texture_2d_array<f32>;
@group(0) @binding(3) var fin_texture: texture_2d<f32>;
@group(0) @binding(4) var tile_sampler: sampler;
@group(0) @binding(5) var fin_sampler: sampler;

// A clip position outside the view volume: a primitive whose corners all go here is dropped.
const CULLED: vec4<f32> = vec4<f32>(2.0, 2.0, 2.0, 1.0);

fn clip_position(p: vec3<f32>) -> vec4<f32> {
    return frame.view_proj * vec4<f32>(p, 1.0);
}

// Unit vector from `p` toward the viewer.
fn view_vector(p: vec3<f32>) -> vec3<f32> {
    return normalize(frame.eye.xyz - p * frame.eye.w);
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
