#define_import_path pelt::body_shadow

// How much of the directional light reaches a point past the body, read from the body's shadow
// map (`shadow_map.rs`): 1 where no part of the skin stands between it and the light, 0 where
// one does, soft over about a texel of the map (the sampler's 2 × 2 comparison). The point is
// first lifted off its own skin along `normal`, so a surface at a slant to the light does not
// shadow itself. `params`: x 1 when the frame draws a map (else every point is lit), y the
// normal offset (object units), z the depth bias. The fur passes read it through `common.wgsl`'s
// `body_shadow`, PRT's rotation pass per vertex.
fn map_visibility(map: texture_depth_2d, compare: sampler_comparison,
                  light_view_proj: mat4x4<f32>, params: vec4<f32>, position: vec3<f32>,
                  normal: vec3<f32>) -> f32 {
    if (params.x == 0.0) {
        return 1.0;
    }
    let clip = light_view_proj * vec4<f32>(position + normal * params.y, 1.0);
    let uv = vec2<f32>(0.5 + 0.5 * clip.x, 0.5 - 0.5 * clip.y);
    return textureSampleCompareLevel(map, compare, uv, clip.z - params.z);
}
