//! Per-frame render settings: which passes run (Lengyel et al. 2001, §2.3), how many shells, how
//! long the fur is in object units (§3: layer spacing × per-vertex length), and the background.

use crate::error::{PeltError, Result};

/// Longest fur accepted, object units.
pub const MAX_FUR_DEPTH: f32 = 1e6;

/// What to draw and how.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RenderSettings {
    /// Shells drawn above the skin, `[0, layers − 1]` of the scene's volume; `None` draws all.
    /// Fewer shells than layers pick evenly spaced layers (shell `i` of `s` shows layer
    /// `round(i · (L − 1) / s)` at that layer's height), so the fur keeps its full length.
    pub shell_count: Option<u32>,
    /// Draw the fins (Lengyel §2.3, pass b).
    pub fins: bool,
    /// Fur depth in object units: the height of the volume's top at length multiplier 1
    /// (`pelt_length`); `[0, MAX_FUR_DEPTH]`.
    pub fur_depth: f32,
    /// Fin opacity before the silhouette fade, `[0, 1]`.
    pub fin_opacity: f32,
    /// Shell fragments whose opacity is below this write no depth and no color (Lengyel §2.3's
    /// alpha test), `[0, 1]`.
    pub alpha_test: f32,
    /// Background, linear straight RGBA, each `[0, 1]`; the default is transparent black, so
    /// alpha shows coverage.
    pub background: [f32; 4],
}

impl Default for RenderSettings {
    fn default() -> Self {
        RenderSettings {
            shell_count: None,
            fins: true,
            fur_depth: 0.05,
            fin_opacity: 1.0,
            alpha_test: 1.0 / 255.0,
            background: [0.0; 4],
        }
    }
}

fn check(name: &str, value: f32, hi: f32) -> Result<()> {
    if value.is_finite() && (0.0..=hi).contains(&value) {
        Ok(())
    } else {
        Err(PeltError::parameter(
            name,
            format!("must be in [0, {hi}], got {value}"),
        ))
    }
}

impl RenderSettings {
    /// Checks every field; returns the number of shells to draw for a volume of `layers` layers.
    pub(super) fn shells_to_draw(&self, layers: u32) -> Result<u32> {
        check("settings.fur_depth", self.fur_depth, MAX_FUR_DEPTH)?;
        check("settings.fin_opacity", self.fin_opacity, 1.0)?;
        check("settings.alpha_test", self.alpha_test, 1.0)?;
        for (i, &c) in self.background.iter().enumerate() {
            check(&format!("settings.background[{i}]"), c, 1.0)?;
        }
        let most = layers.saturating_sub(1);
        match self.shell_count {
            None => Ok(most),
            Some(n) if n <= most => Ok(n),
            Some(n) => Err(PeltError::parameter(
                "settings.shell_count",
                format!("must be in [0, {most}] (the scene's volume has {layers} layers), got {n}"),
            )),
        }
    }
}
