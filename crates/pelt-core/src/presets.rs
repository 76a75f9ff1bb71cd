//! Named fur presets: their one home, read by `pelt bake --preset mink` and, as `pelt.PRESETS`,
//! by the add-on's preset menu. Hair lengths are shares of the fur
//! depth and widths tile units ([`HairParams`]); `fur_depth` and `tile_size` are object units,
//! chosen for an object about 2 units across.

use serde::Serialize;

use crate::error::{PeltError, Result};
use crate::hair::{CoatParams, HairParams};
use crate::pipeline::BakeParams;

/// One preset.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FurPreset {
    /// Name as the add-on spells it (`MINK`); the command line accepts any case.
    pub name: &'static str,
    /// Display name.
    pub label: &'static str,
    /// One line about the look.
    pub description: &'static str,
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

/// Every preset, in the add-on's order.
pub const PRESETS: [FurPreset; 4] = [
    FurPreset {
        name: "SHORT_VELVET",
        label: "Short Velvet",
        description: "Very dense, short, upright pile with no guard hairs",
        density: 32768,
        guard_fraction: 0.0,
        undercoat_length: [0.8, 0.95],
        undercoat_width: [0.003, 0.004],
        overcoat_length: [0.95, 1.0],
        overcoat_width: [0.004, 0.005],
        curl: 0.02,
        helix_radius: 0.0,
        helix_frequency: 0.0,
        slant: 0.05,
        length_jitter: 0.05,
        clump_strength: 0.0,
        clump_count: 0,
        root_color: [0.10, 0.02, 0.04],
        tip_color: [0.35, 0.05, 0.10],
        fur_depth: 0.012,
        tile_size: 0.1,
    },
    FurPreset {
        name: "MINK",
        label: "Mink",
        description: "Dense soft underfur under glossy, slanted guard hairs",
        density: 24576,
        guard_fraction: 0.08,
        undercoat_length: [0.5, 0.7],
        undercoat_width: [0.004, 0.005],
        overcoat_length: [0.9, 1.0],
        overcoat_width: [0.006, 0.008],
        curl: 0.05,
        helix_radius: 0.0,
        helix_frequency: 0.0,
        slant: 0.35,
        length_jitter: 0.1,
        clump_strength: 0.0,
        clump_count: 0,
        root_color: [0.05, 0.03, 0.02],
        tip_color: [0.22, 0.12, 0.06],
        fur_depth: 0.04,
        tile_size: 0.15,
    },
    FurPreset {
        name: "LONG_SHAGGY",
        label: "Long Shaggy",
        description: "Long, clumped, strongly slanted and uneven hair",
        density: 8192,
        guard_fraction: 0.15,
        undercoat_length: [0.4, 0.7],
        undercoat_width: [0.005, 0.007],
        overcoat_length: [0.8, 1.0],
        overcoat_width: [0.008, 0.010],
        curl: 0.3,
        helix_radius: 0.0,
        helix_frequency: 0.0,
        slant: 0.6,
        length_jitter: 0.3,
        clump_strength: 0.5,
        clump_count: 48,
        root_color: [0.20, 0.16, 0.11],
        tip_color: [0.70, 0.62, 0.48],
        fur_depth: 0.12,
        tile_size: 0.25,
    },
    FurPreset {
        name: "CURLY",
        label: "Curly",
        description: "Tight helical curls gathered in small clumps",
        density: 12288,
        guard_fraction: 0.0,
        undercoat_length: [0.6, 0.9],
        undercoat_width: [0.005, 0.007],
        overcoat_length: [0.9, 1.0],
        overcoat_width: [0.006, 0.008],
        curl: 0.4,
        helix_radius: 0.02,
        helix_frequency: 3.0,
        slant: 0.2,
        length_jitter: 0.15,
        clump_strength: 0.3,
        clump_count: 64,
        root_color: [0.30, 0.24, 0.18],
        tip_color: [0.85, 0.80, 0.70],
        fur_depth: 0.06,
        tile_size: 0.12,
    },
];

impl FurPreset {
    /// The preset named `name`, any case, `-` or `_` between words (`long-shaggy`).
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] naming `preset` and listing the names.
    pub fn find(name: &str) -> Result<&'static FurPreset> {
        let wanted = name.trim().to_ascii_uppercase().replace('-', "_");
        PRESETS.iter().find(|p| p.name == wanted).ok_or_else(|| {
            let names: Vec<String> = PRESETS.iter().map(|p| p.name.to_ascii_lowercase()).collect();
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
