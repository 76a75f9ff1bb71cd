//! Pass (c), marched ([`super::ShellMethod::Marched`]): the shells as one hull whose fragments
//! march down through the layers (`marched.wgsl`), instead of one instanced mesh per shell. Same
//! state as the instanced pass: back faces culled, depth written behind the alpha test,
//! premultiplied "over" the skin and fins; [`super::shells::ShellsPass`] owns and draws it.

use super::pass::Model;

const KAJIYA_KAY: &str = concat!(
    include_str!("common.wgsl"),
    include_str!("lighting.wgsl"),
    include_str!("surface.wgsl"),
    include_str!("surface_kk.wgsl"),
    include_str!("march.wgsl"),
    include_str!("marched.wgsl")
);
const PRT: &str = concat!(
    include_str!("common.wgsl"),
    include_str!("prt.wgsl"),
    include_str!("surface.wgsl"),
    include_str!("surface_prt.wgsl"),
    include_str!("march.wgsl"),
    include_str!("marched.wgsl")
);

/// The marched hull's shader for `model`.
pub(super) fn source(model: Model) -> &'static str {
    match model {
        Model::KajiyaKay => KAJIYA_KAY,
        Model::Prt => PRT,
    }
}
