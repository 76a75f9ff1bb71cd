//! Named fur presets: their one home is the data file `presets.json` beside this crate, read by
//! `pelt bake --preset mink` and, as `pelt.PRESETS`, by the add-on's preset menu. Hair lengths
//! are shares of the fur depth and widths tile units ([`HairParams`]); `fur_depth` and
//! `tile_size` are object units, chosen for an object about 2 units across.

use std::sync::LazyLock;

use serde::{Deserialize, Serialize};

use crate::error::{PeltError, Result};
use crate::hair::{CoatParams, HairParams};
use crate::pipeline::BakeParams;

/// One preset.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FurPreset {
    /// Name as the add-on spells it (`MINK`); the command line accepts any case.
    pub name: String,
    /// Display name.
    pub label: String,
    /// One line about the look.
    pub description: String,
    /// Hairs per tile.
    pub density: u32,
    /// Share of guard hairs.
    pub guard_fraction: f64,
    /// Undercoat `[min, max]` length, fur depths.
    pub undercoat_length: [f64; 2],
    /// Undercoat `[min, max]` width, tile units.
    pub undercoat_width: [f64; 2],
    /// Overcoat `[min, max]` length.
    pub overcoat_length: [f64; 2],
    /// Overcoat `[min, max]` width.
    pub overcoat_width: [f64; 2],
    /// Parabolic curl.
    pub curl: f64,
    /// Helix radius, tile units.
    pub helix_radius: f64,
    /// Helix turns.
    pub helix_frequency: f64,
    /// Slant, radians.
    pub slant: f64,
    /// Random shortening.
    pub length_jitter: f64,
    /// Pull toward clump centres.
    pub clump_strength: f64,
    /// Clump centres per tile.
    pub clump_count: u32,
    /// Linear root color.
    pub root_color: [f32; 3],
    /// Linear tip color.
    pub tip_color: [f32; 3],
    /// Fur height at length 1, object units.
    pub fur_depth: f64,
    /// Object units per tile.
    pub tile_size: f64,
}

/// The presets' data file, in the add-on's order (Rust reads it here; the add-on through
/// `pelt.PRESETS`).
const PRESETS_JSON: &str = include_str!("../presets.json");

/// Every preset, in the add-on's order, parsed from `presets.json` once.
pub fn presets() -> &'static [FurPreset] {
    static PRESETS: LazyLock<Vec<FurPreset>> = LazyLock::new(|| {
        // The file is compiled in and a test parses and checks it, so this cannot fail at run time.
        serde_json::from_str(PRESETS_JSON).expect("presets.json parses (checked by a test)")
    });
    &PRESETS
}

impl FurPreset {
    /// The preset named `name`, any case, `-` or `_` between words (`long-shaggy`).
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] naming `preset` and listing the names.
    pub fn find(name: &str) -> Result<&'static FurPreset> {
        let wanted = name.trim().to_ascii_uppercase().replace('-', "_");
        presets().iter().find(|p| p.name == wanted).ok_or_else(|| {
            let names: Vec<String> = presets().iter().map(|p| p.name.to_ascii_lowercase()).collect();
            PeltError::parameter("preset", format!("{name:?} is not one of {}", names.join(", ")))
        })
    }

    /// Writes the preset's hair, fur depth and tile size into `params` (the rest is kept).
    pub fn apply(&self, params: &mut BakeParams) {
        let hair: &mut HairParams = &mut params.hair;
        hair.density = self.density;
        hair.guard_fraction = self.guard_fraction;
        hair.undercoat = CoatParams {
            length: self.undercoat_length,
            width: self.undercoat_width,
        };
        hair.overcoat = CoatParams {
            length: self.overcoat_length,
            width: self.overcoat_width,
        };
        hair.curl = self.curl;
        hair.helix_radius = self.helix_radius;
        hair.helix_frequency = self.helix_frequency;
        hair.slant = self.slant;
        hair.length_jitter = self.length_jitter;
        hair.clump_strength = self.clump_strength;
        hair.clump_count = self.clump_count;
        hair.root_color = self.root_color;
        hair.tip_color = self.tip_color;
        params.fur_depth = Some(self.fur_depth);
        params.patches.tile_size = self.tile_size;
    }
}

#[cfg(test)]
mod tests {
    use super::{FurPreset, presets};
    use crate::pipeline::BakeParams;

    #[test]
    fn every_preset_is_a_bake_inside_the_schema_s_ranges() {
        assert_eq!(presets().len(), 4);
        for preset in presets() {
            let mut params = BakeParams::default();
            preset.apply(&mut params);
            // Checks every set's ranges, the preset's fur depth and tile size among them.
            params.validate_ranges().unwrap();
            assert_eq!(FurPreset::find(&preset.name.to_lowercase()).unwrap(), preset);
        }
    }
}
