//! The world lighting of PRT as SH coefficients (prt-shell-fur §2.4): the environment plus the
//! directional light projected as a uniform cap (the paper lights its fur with "one
//! low-frequency lobe of light" rotated every frame), at the order of the scene's transfer.

use std::f64::consts::PI;

use super::lighting::LightingFrame;
use pelt_core::error::Result;
use pelt_core::prt::sh;

/// The world lighting of PRT in object space, RGB per coefficient (`w` = 0), divided by π (see
/// [`super::Prt`]): the environment, and the directional light apart, since the rotation pass
/// fades it out past each vertex's terminator (`prt_rotate.wgsl`).
#[derive(Debug, Clone, PartialEq)]
pub(super) struct WorldLighting {
    pub environment: Vec<[f32; 4]>,
    pub sun: Vec<[f32; 4]>,
    /// Unit direction toward the directional light.
    pub sun_direction: [f32; 3],
}

/// The world lighting for a transfer of `order` bands. The environment is truncated or padded
/// with zeros to `order`; the light of irradiance `E` (`Lighting::color`, which the frame holds
/// as `E / π`) enters as `E` times the unit-power cap around its direction, so that unshadowed
/// it gives `albedo · E / π`, as the environment's own suns do.
///
/// # Errors
/// None for a lighting that passed [`super::Lighting::frame`] and an order in `[1, 8]`.
pub(super) fn world_coefficients(light: &LightingFrame, order: usize) -> Result<WorldLighting> {
    let n = sh::coeff_count(order);
    let mut out = WorldLighting {
        environment: vec![[0.0f32; 4]; n],
        sun: vec![[0.0f32; 4]; n],
        sun_direction: light.direction,
    };
    let Some(prt) = &light.prt else {
        return Ok(out);
    };
    let cap = sh::project_cap(order, light.direction.map(f64::from), f64::from(prt.light_radius))?;
    let rows = out.environment.iter_mut().zip(out.sun.iter_mut()).zip(&cap);
    for (k, ((environment, sun), &cap)) in rows.enumerate() {
        let world = prt.environment.get(k).copied().unwrap_or([0.0; 3]);
        for c in 0..3 {
            environment[c] = (f64::from(world[c]) / PI) as f32;
            sun[c] = (f64::from(light.color[c]) * cap) as f32;
        }
    }
    Ok(out)
}
