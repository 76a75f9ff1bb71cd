// Pass (a), the skin (Lengyel et al. 2001, §2.3): the mesh itself, opaque, textured with layer 0
// of the shell texture times the vertex color; it fills the depth buffer. The lighting model
// (`light_model.wgsl`) provides `SkinVarying`, `skin_vertex` and `skin_fragment`.

// PRT's skin varies as its surface does: its `SurfaceVarying` is the skin's.
#ifdef PRT
#import pelt::surface_prt::{SurfaceIn, SurfaceVarying as SkinVarying, skin_vertex, skin_fragment}
#else
#import pelt::surface_kk::{SurfaceIn, SkinVarying, skin_vertex, skin_fragment}
#endif

@vertex
fn vs_main(v: SurfaceIn) -> SkinVarying {
    // Both models light the skin under the fur painted over it: bald skin is a bare Lambertian
    // surface (Kajiya–Kay: no Banks darkening, no terminator band; PRT: `painted_skin`).
    return skin_vertex(v);
}

@fragment
fn fs_main(s: SkinVarying) -> @location(0) vec4<f32> {
    return vec4<f32>(skin_fragment(s), 1.0);
}
