//! The bake's own numbers and switches as the parameter schema exports them (`pelt.SCHEMA["bake"]`):
//! what a front end (`Pipeline.bake`, `pelt bake`, the add-on) passes beside the nested sets, which
//! have schemas of their own.

use serde::{Deserialize, Serialize};

use super::{BakeParams, TransferChoice};
use crate::mesh::FUR_DEPTH;
use crate::params::{Range, Schema};
use crate::prt::Phase;
use crate::prt::bands::BandParams;
use crate::volume::PlaneParams;
use crate::volume::slices::MAX_PLANES;

/// The bake's own keywords, with their defaults.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BakeKeywords {
    /// Object units; `None` is one tile width.
    pub fur_depth: Option<f64>,
    /// The front ends bake the transfer unless told not to (PRT lighting reads it);
    /// [`BakeParams::default`] leaves it out, for a library user who lights with Kajiya–Kay.
    pub transfer: bool,
    /// `None` picks the order by band selection within `tolerance`.
    pub order: Option<usize>,
    pub tolerance: f64,
    pub phase: Phase,
    /// Planes per family of the virtual-planes slices; 0 bakes none.
    pub planes: usize,
}

impl Default for BakeKeywords {
    fn default() -> Self {
        let bake = BakeParams::default();
        let choice = TransferChoice::default();
        BakeKeywords {
            fur_depth: bake.fur_depth,
            transfer: true,
            order: (!choice.auto).then_some(choice.params.order),
            tolerance: choice.bands.tolerance,
            phase: choice.params.phase,
            planes: bake.planes.map_or(0, |p| p.planes),
        }
    }
}

impl BakeKeywords {
    /// `base` with these keywords' choices.
    pub fn apply(&self, base: BakeParams) -> BakeParams {
        let transfer = self.transfer.then(|| {
            let mut choice = TransferChoice {
                auto: self.order.is_none(),
                ..TransferChoice::default()
            };
            choice.params.order = self.order.unwrap_or(choice.params.order);
            choice.params.phase = self.phase;
            choice.bands.tolerance = self.tolerance;
            choice
        });
        BakeParams {
            fur_depth: self.fur_depth,
            transfer,
            planes: (self.planes > 0).then(|| PlaneParams {
                planes: self.planes,
                ..PlaneParams::default()
            }),
            ..base
        }
    }
}

/// Planes per family as the front ends count them: 0 bakes no slices.
pub(super) const PLANES: Range = Range::closed("planes", 0.0, MAX_PLANES as f64, "planes per family");

impl BakeParams {
    /// The ranges of the bake's own numbers.
    pub const RANGES: &'static [Range] = &[FUR_DEPTH, BandParams::RANGES[0], PLANES];
}

/// Every parameter set's schema of the bake (the renderer adds its own,
/// `pelt_render::RenderSettings::schema`).
pub fn schemas() -> Vec<Schema> {
    let mut patches =
        Schema::new::<crate::lapped::PatchParams>("patches", crate::lapped::PatchParams::RANGES);
    // The comb field's numbers are a set of their own (Python passes them flat, as `blend`).
    if let Some(map) = patches.defaults.as_object_mut() {
        map.remove("field");
    }
    vec![
        Schema::new::<BakeKeywords>("bake", BakeParams::RANGES),
        patches,
        Schema::new::<crate::field::FieldParams>("field", crate::field::FieldParams::RANGES),
        Schema::new::<crate::hair::HairParams>("hair", crate::hair::HairParams::RANGES),
        Schema::new::<crate::volume::VolumeParams>("volume", crate::volume::VolumeParams::RANGES),
        Schema::new::<crate::prt::TransferParams>("transfer", crate::prt::TransferParams::RANGES),
    ]
}

#[cfg(test)]
#[path = "schema_tests.rs"]
mod tests;
