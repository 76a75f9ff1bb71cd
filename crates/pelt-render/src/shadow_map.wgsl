// The body's shadow map (`shadow_map.rs`): the skin's depth as the directional light sees it.

@group(0) @binding(0) var<uniform> light_view_proj: mat4x4<f32>;

@vertex
fn vs_main(@location(0) position: vec3<f32>) -> @builtin(position) vec4<f32> {
    return light_view_proj * vec4<f32>(position, 1.0);
}
