#define_import_path pelt::strand_prt

#import pelt::prt::{mean_radiance, hot_spot}
#import pelt::light_model::StrandOut

// Guard hairs under PRT lighting: a strand has no transfer of its own, so it takes the hair's
// mean transfer at its height (as the fins do, `fin_prt.wgsl`), lit by the rotated lighting of
// its root triangle's vertices: shadowed as the volume around it is.

fn shade_strand(v: StrandOut, tangent: vec3<f32>, height: f32) -> vec4<f32> {
    let lit = mean_radiance(v.corners, v.weights, height, hot_spot(v.position));
    return vec4<f32>(v.color.rgb * lit, v.color.a);
}
