//! The world lighting of PRT as SH coefficients (prt-shell-fur §2.4): the environment plus the
//! directional light projected as a uniform cap (the paper lights its fur with "one
//! low-frequency lobe of light" rotated every frame), at the order of the scene's transfer.

use std::f64::consts::PI;

use super::lighting::LightingFrame;
use crate::error::Result;
use crate::prt::sh;

/// The world lighting for a transfer of `order` bands, RGB per coefficient (`w` = 0), divided
/// by π (see [`super::Prt`]). The environment is truncated or padded with zeros to `order`; the
/// light of irradiance `E` (`Lighting::color`, which the frame holds as `E / π`) enters as `E`
/// times the unit-power cap around its direction, so that unshadowed it gives `albedo · E / π`,
/// as the environment's own suns do.
///
/// # Errors
/// None for a lighting that passed [`super::Lighting::frame`] and an order in `[1, 8]`.
pub(super) fn world_coefficients(light: &LightingFrame, order: usize) -> Result<Vec<[f32; 4]>> {
    let n = sh::coeff_count(order);
    let mut out = vec![[0.0f32; 4]; n];
    let Some(prt) = &light.prt else {
        return Ok(out);
    };
    let cap = sh::project_cap(order, light.direction.map(f64::from), f64::from(prt.light_radius))?;
    for (k, row) in out.iter_mut().enumerate() {
        let environment = prt.environment.get(k).copied().unwrap_or([0.0; 3]);
        for c in 0..3 {
            let value = f64::from(environment[c]) / PI + f64::from(light.color[c]) * cap[k];
            row[c] = value as f32;
        }
    }
    Ok(out)
}
