#define_import_path pelt::strand_kk

#import pelt::common::{view_vector, body_shadow}
#import pelt::lighting::shade
#import pelt::light_model::StrandOut

// Guard hairs under Kajiya-Kay lighting: the shells' hair terms with the strand's own tangent,
// Banks-darkened by the height it stands at under its root's painted length, as the shell texel
// there would be.

fn shade_strand(v: StrandOut, tangent: vec3<f32>, height: f32) -> vec4<f32> {
    return shade(v.color.rgb, v.color.a, tangent, v.normal, view_vector(v.position), height,
                 v.wrap_length.y, v.wrap_length.x, body_shadow(v.position, v.normal));
}
