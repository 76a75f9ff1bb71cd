//! Pass (c), marched ([`super::ShellMethod::Marched`]): the shells as one hull whose fragments
//! march down through the layers (`marched.wgsl`), instead of one instanced mesh per shell. Same
//! state as the instanced pass: back faces culled, depth written behind the alpha test,
//! premultiplied "over" the skin and fins; [`super::shells::ShellsPass`] owns and draws it.

use super::shaders::PassShader;

/// The marched hull's shader, one source for both lighting models.
pub(super) static SHADER: PassShader = PassShader::new("marched.wgsl", include_str!("marched.wgsl"));
