// Pass (c), the shells (Lengyel et al. 2001, §2.3): every shell in one instanced draw, instance
// order = inner to outer, each lifted in this vertex shader (§2.4, "Programmable vertex shaders").

#import pelt::common::{
    frame, Layers, shell_layers, shell_stand, shading_height, hair_density, spread_out,
}
#import pelt::surface::{layer_texels, blended, uv_gradients}
#ifdef PRT
#import pelt::surface_prt as model
#else
#import pelt::surface_kk as model
#endif

@vertex
fn vs_main(v: model::SurfaceIn, @builtin(instance_index) instance: u32) -> model::SurfaceVarying {
    let layers = shell_layers(instance);
    return model::surface_vertex(v, layers, shell_stand(layers), true);
}

@fragment
fn fs_main(v: model::SurfaceVarying) -> @location(0) vec4<f32> {
    let s = model::surface_fragment(v);
    let texels = layer_texels(s.uv, s.layer, s.coarse);
    let grad = uv_gradients(s.uv);
    let wrap = model::surface_wrap(s);
    let layers = Layers(s.height, s.layer, s.coarse);
    let spread = model::surface_spread(s, shell_stand(layers) * frame.fur.y);
    // Bald faces (length 0 at every corner) draw nothing; the alpha test keeps empty texels from
    // writing depth over the layers still to come, and spares them the lighting.
    if (s.length <= 0.0 || blended(texels).a * s.color.a < frame.fur.w) {
        discard;
    }
    // Thinned (or crowded) as the hair stands at the shell's height over its triangle: the
    // lighting is linear in the texel, so the lit texel is thinned as the texel would be (PRT's
    // transfer is premultiplied by the tile's own opacity).
    let density = hair_density(spread, shading_height(layers) * frame.fur.y);
    return spread_out(model::shade_surface(s, texels, s.color.a, grad, wrap), density);
}
