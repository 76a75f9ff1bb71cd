//! The staged bake (DESIGN.md §1): mesh → lapped patches, hair parameters → hair volume, then the
//! optional guard hairs (the overcoat placed as strands), virtual-plane slices and PRT transfer,
//! gathered in a [`FurAsset`]. Each stage is keyed by a hash of exactly the inputs it reads
//! ([`key`]); a [`Pipeline`] keeps the last result of each stage, so a re-bake runs only what
//! changed (a new vertex color runs only the guard hairs' placement, when they are on; a new comb
//! the patches and what is placed over them; new hair parameters the volume and what follows) and
//! reports per stage whether it ran and how long it took.

mod key;
mod schema;
#[cfg(test)]
mod tests;

use std::sync::Arc;
use std::time::Instant;

use serde::Serialize;

use crate::FurMesh;
use crate::error::{PeltError, Result};
use crate::hair::HairParams;
use crate::lapped::{self, PatchParams, Patches};
use crate::placement::PlacedStrands;
use crate::progress::ProgressCallback;
use crate::prt::bands::{BandParams, BandReport, bake_transfer_auto};
use crate::prt::pack::{PackedF16, PackedU8, pack_f16, pack_u8};
use crate::prt::transfer::{MAX_LAYER_SPACING, MAX_LAYERS, MAX_VOXELS};
use crate::prt::volume_input::VolumeInput;
use crate::prt::{Phase, Transfer, TransferParams, bake_transfer};
use crate::volume::{HairVolume, PlaneParams, PlaneSlices, VolumeParams, bake_slices, bake_volume};

use key::{KeyHasher, patch_mesh_key};

pub use schema::{BakeKeywords, schemas};

pub use crate::mesh::{FUR_DEPTH, MAX_FUR_DEPTH};

/// Stage names, in the order they run.
pub const STAGES: [&str; 5] = ["patches", "volume", "guard_hairs", "planes", "transfer"];

/// Reports `(stage, finished fraction of that stage)`; returns `false` to cancel the bake.
pub type StageCallback<'a> = &'a (dyn Fn(&str, f64) -> bool + Sync);

/// How the transfer (PRT) is baked.
#[derive(Debug, Clone, PartialEq)]
pub struct TransferChoice {
    /// Bake settings; `params.order` is used only when `auto` is false.
    pub params: TransferParams,
    /// Pick the order by band selection (`bands.tolerance`) instead of `params.order`.
    pub auto: bool,
    /// Band selection settings (used when `auto`).
    pub bands: BandParams,
}

impl Default for TransferChoice {
    fn default() -> Self {
        TransferChoice {
            // The hair tangents are baked with the volume, so the Kajiya–Kay phase costs nothing.
            params: TransferParams {
                phase: Phase::KajiyaKay,
                ..TransferParams::default()
            },
            auto: true,
            bands: BandParams::default(),
        }
    }
}

/// Everything a bake reads besides the mesh.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct BakeParams {
    /// Comb field and lapped patches; `patches.tile_size` is the object-space width of one tile.
    pub patches: PatchParams,
    /// The hair grown in a tile.
    pub hair: HairParams,
    /// How the hair is sampled into shells.
    pub volume: VolumeParams,
    /// Fur height at length multiplier 1, object units, [`FUR_DEPTH`]; `None` takes one
    /// tile width (the strands' own proportions).
    pub fur_depth: Option<f64>,
    /// The PRT bake; `None` skips it (Kajiya–Kay lighting needs no transfer).
    pub transfer: Option<TransferChoice>,
    /// The slices of the virtual-planes renderer
    /// (`pelt_render::ShellMethod::VirtualPlanes`); `None` (default) skips them,
    /// since only that method reads them.
    pub planes: Option<PlaneParams>,
}

impl BakeParams {
    /// Fur height, object units.
    pub fn fur_depth(&self) -> f64 {
        self.fur_depth.unwrap_or(self.patches.tile_size)
    }

    /// The hair the volume is grown with over `mesh`: [`HairParams::under_paint`] when the mesh
    /// carries painted colors, so they show as painted, else the coat as set.
    pub fn grown_hair(&self, mesh: &FurMesh) -> HairParams {
        self.hair.under_paint(mesh.color().is_some())
    }

    /// Checks every stage's parameters and the bake's memory, so a bad one fails before any
    /// stage runs.
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] naming the first field out of range;
    /// [`PeltError::MemoryLimit`] when [`Self::peak_bytes`] is above the limit.
    pub fn validate(&self) -> Result<()> {
        self.validate_ranges()?;
        self.check_memory()
    }

    /// [`Self::validate`] without the memory check.
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] naming the first field out of range.
    pub fn validate_ranges(&self) -> Result<()> {
        self.patches.validate()?;
        self.hair.validate()?;
        self.volume.validate()?;
        let depth = self.fur_depth();
        if self.fur_depth.is_some() {
            FUR_DEPTH.check(depth)?;
        } else if !FUR_DEPTH.contains(depth) {
            // The depth defaults to the tile size: name what the user set.
            return Err(PeltError::parameter(
                "tile_size",
                format!(
                    "must be in (0, {MAX_FUR_DEPTH}] object units when `fur_depth` is not given \
                     (the fur is one tile deep), got {depth:e}"
                ),
            ));
        }
        if let Some(choice) = &self.transfer {
            choice.params.validate()?;
            choice.bands.validate()?;
            self.check_transfer_volume()?;
        }
        if self.volume.guard_hairs {
            crate::guard::validate(&self.hair, depth, self.volume.guard_share)?;
        }
        if let Some(planes) = &self.planes {
            // The count as the front ends take it (0: no slices), then the slices' own checks.
            schema::PLANES.check(planes.planes as f64)?;
            planes.validate()?;
        }
        Ok(())
    }

    /// What the transfer stage asks of the volume, checked before any stage runs: two layers at
    /// least, at most [`MAX_VOXELS`] voxels, and a layer spacing (the fur depth in texel widths
    /// per layer) the transfer can represent.
    fn check_transfer_volume(&self) -> Result<()> {
        let (layers, res) = (self.volume.layers, self.volume.resolution);
        if layers < 2 {
            return Err(PeltError::parameter(
                "layers",
                format!(
                    "must be in [2, {MAX_LAYERS}] when a transfer is baked (layer 0 is the skin), got {layers}"
                ),
            ));
        }
        let voxels = layers * res * res;
        if voxels > MAX_VOXELS {
            return Err(PeltError::parameter(
                "resolution",
                format!(
                    "layers·resolution² must be at most {MAX_VOXELS} when a transfer is baked, got \
                     {layers}·{res}² = {voxels}"
                ),
            ));
        }
        let texels_per_depth = res as f64 / (layers as f64 * self.patches.tile_size);
        let spacing = self.fur_depth() * texels_per_depth;
        let (lo, hi) = (f64::from(f32::MIN_POSITIVE), f64::from(MAX_LAYER_SPACING));
        if !(lo..=hi).contains(&spacing) {
            let name = if self.fur_depth.is_some() {
                "fur_depth"
            } else {
                "tile_size"
            };
            return Err(PeltError::parameter(
                name,
                format!(
                    "gives {spacing:e} texel widths between layers, outside [{lo:e}, {hi:e}]: keep \
                     fur_depth (here {}) in [{:e}, {:e}] object units for tile_size {}, resolution \
                     {res} and {layers} layers",
                    self.fur_depth(),
                    lo / texels_per_depth,
                    hi / texels_per_depth,
                    self.patches.tile_size
                ),
            ));
        }
        Ok(())
    }

    /// Estimated peak bytes of the bake: the volume stage's, or the volume kept while the
    /// transfer is baked and packed, whichever is larger (the patches are the mesh's size).
    pub fn peak_bytes(&self) -> f64 {
        let volume = crate::volume::peak::grown_volume_peak_bytes(&self.volume, &self.hair);
        let transfer = self.transfer.as_ref().map_or(0.0, |choice| {
            let (l, r) = (self.volume.layers, self.volume.resolution);
            // The transfer's own tangents and path density (`VolumeInput`): 16 bytes per voxel.
            crate::volume::peak::volume_bytes(&self.volume)
                + 16.0 * (l * r * r) as f64
                + crate::prt::peak::transfer_peak_bytes(l, r, &choice.params, choice.auto, true)
        });
        // The slices are baked with the volume held, from strands grown again.
        let planes = self.planes.as_ref().map_or(0.0, |p| {
            crate::volume::peak::volume_bytes(&self.volume)
                + crate::volume::peak::strand_bytes(&self.hair)
                + p.peak_bytes()
        });
        volume.max(transfer).max(planes)
    }

    /// `Ok` when [`Self::peak_bytes`] fits the memory limit.
    fn check_memory(&self) -> Result<()> {
        crate::memory::check("bake", self.peak_bytes(), || {
            let order = match &self.transfer {
                Some(TransferChoice {
                    auto: false, params, ..
                }) => format!(", `order` ({})", params.order),
                Some(_) => ", the transfer's automatic order (bakes 8)".into(),
                None => String::new(),
            };
            format!(
                "`resolution` ({}), `layers` ({}), the hair `density` ({}){order}",
                self.volume.resolution, self.volume.layers, self.hair.density
            )
        })
    }
}

/// The transfer of a volume, packed for textures.
#[derive(Debug, Clone)]
pub struct TransferBake {
    /// Coefficients per voxel.
    pub transfer: Transfer,
    /// The band table when the order was picked by band selection.
    pub bands: Option<BandReport>,
    /// Float16 textures (4 coefficients each).
    pub packed_f16: PackedF16,
    /// 8-bit textures with their scale and bias sidecar.
    pub packed_u8: PackedU8,
    /// Fur depth in tile widths the transfer was baked for.
    pub depth_in_tiles: f64,
}

/// One stage of a bake: whether it ran or was reused, its time and a one-line summary.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StageReport {
    /// One of [`STAGES`].
    pub stage: String,
    /// False when the previous result was reused because its inputs had not changed.
    pub ran: bool,
    /// Seconds spent (0 when reused).
    pub seconds: f64,
    /// Figures of the result, e.g. "14 patches, mean alignment 1.4°".
    pub summary: String,
}

/// The result of a bake: every stage's output, shared (cheap to clone).
#[derive(Debug, Clone)]
pub struct FurAsset {
    /// The mesh the bake read.
    pub mesh: Arc<FurMesh>,
    /// Lapped patches: per-corner UVs in tile units and patch ids.
    pub patches: Arc<Patches>,
    /// The hair volume (without the guard hairs drawn as strands, when there are some).
    pub volume: Arc<HairVolume>,
    /// The guard hairs over the mesh, when the volume was baked with
    /// [`VolumeParams::guard_hairs`](crate::volume::VolumeParams::guard_hairs).
    pub guard_hairs: Option<Arc<PlacedStrands>>,
    /// The transfer, when asked for.
    pub transfer: Option<Arc<TransferBake>>,
    /// The virtual planes' slices, when asked for ([`BakeParams::planes`]).
    pub planes: Option<Arc<PlaneSlices>>,
    /// The parameters of the bake.
    pub params: BakeParams,
    /// Per stage, in order: ran or reused, seconds, summary.
    pub report: Vec<StageReport>,
}

struct Cached<T> {
    key: u64,
    value: Arc<T>,
}

/// Keeps the last result of each stage so a re-bake runs only what changed.
#[derive(Default)]
pub struct Pipeline {
    patches: Option<Cached<Patches>>,
    volume: Option<Cached<HairVolume>>,
    guard_hairs: Option<Cached<PlacedStrands>>,
    planes: Option<Cached<PlaneSlices>>,
    transfer: Option<Cached<TransferBake>>,
}

impl Pipeline {
    /// An empty cache.
    pub fn new() -> Self {
        Self::default()
    }

    /// Forgets every cached stage.
    pub fn clear(&mut self) {
        *self = Self::default();
    }

    /// Bakes `mesh` with `params`, reusing each stage whose inputs equal the last bake's.
    /// `progress` hears `(stage, fraction)` and may cancel; stages finished before a cancel stay
    /// cached (they are complete), and nothing of the cancelled stage is kept.
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] for a bad parameter (before any stage runs), the stages'
    /// own errors, [`PeltError::Cancelled`] when `progress` returned `false`.
    pub fn bake(
        &mut self,
        mesh: Arc<FurMesh>,
        params: &BakeParams,
        progress: Option<StageCallback<'_>>,
    ) -> Result<FurAsset> {
        params.validate()?;
        let mut report = Vec::with_capacity(STAGES.len());

        let patch_key = patch_mesh_key(KeyHasher::new("patches"), &mesh)
            .params(&params.patches)
            .finish();
        let patches = run_stage(&mut self.patches, patch_key, "patches", &mut report, || {
            let callback = stage_callback(progress, "patches");
            let call = |f: f64| callback.as_ref().is_none_or(|c| c(f));
            let patches = lapped::build_patches_with_progress(&mesh, &params.patches, Some(&call))?;
            let q = &patches.quality;
            let summary = format!(
                "{} patches over {} faces, mean alignment {:.2}°, {:.1}% within stretch",
                q.patch_count,
                q.furred_faces,
                q.mean_alignment_deg,
                100.0 * q.stretch_within_fraction
            );
            Ok((patches, summary))
        })?;

        // Painted colors change the coat's colors (not which stage runs when they are repainted).
        let hair = params.grown_hair(&mesh);
        let volume_key_of = |hair: &HairParams| {
            KeyHasher::new("volume")
                .params(hair)
                .params(&params.volume)
                .finish()
        };
        let volume_key = volume_key_of(&hair);
        // The transfer reads the volume's coverage, never its colors: painting does not re-run it.
        let coverage_key = volume_key_of(&params.hair);
        let volume = run_stage(&mut self.volume, volume_key, "volume", &mut report, || {
            let callback = stage_callback(progress, "volume");
            let call = |f: f64| callback.as_ref().is_none_or(|c| c(f));
            let volume = bake_volume(&hair, &params.volume, Some(&call))?;
            let s = &volume.stats;
            let summary = format!(
                "{} strands, {} layers of {}² ({} trimmed), fin {}×{}",
                s.strands, s.layers, volume.resolution, s.trimmed, volume.fin_size[0], volume.fin_size[1]
            );
            Ok((volume, summary))
        })?;

        let guard_hairs = if params.volume.guard_hairs {
            // Placement reads the patches, the hair, the depth, and the lengths and colors painted.
            let guard_key = KeyHasher::new("guard_hairs")
                .key(patch_key)
                .params(&hair)
                .params(&params.fur_depth())
                .params(&params.volume.guard_share)
                .ints(mesh.length().unwrap_or_default().iter().map(|l| l.to_bits()))
                .floats(mesh.color())
                .finish();
            Some(run_stage(
                &mut self.guard_hairs,
                guard_key,
                "guard_hairs",
                &mut report,
                || {
                    let share = params.volume.guard_share;
                    let placed =
                        crate::guard::guard_hairs(&mesh, &patches, &hair, params.fur_depth(), share)?;
                    let summary = format!(
                        "{} guard hairs, {} points",
                        placed.spans.len(),
                        placed.points.len()
                    );
                    Ok((placed, summary))
                },
            )?)
        } else {
            self.guard_hairs = None;
            None
        };

        let planes = match &params.planes {
            None => {
                self.planes = None;
                None
            }
            Some(plane_params) => {
                // The shells' hair (guard hairs drawn as strands left out), sliced.
                let planes_key = KeyHasher::new("planes")
                    .key(volume_key)
                    .params(plane_params)
                    .finish();
                Some(run_stage(
                    &mut self.planes,
                    planes_key,
                    "planes",
                    &mut report,
                    || {
                        let callback = stage_callback(progress, "planes");
                        let call = |f: f64| callback.as_ref().is_none_or(|c| c(f));
                        let strands = crate::hair::grow_strands(&hair)?;
                        let drawn = if params.volume.guard_hairs {
                            crate::guard::drawn_as_strands(&strands, params.volume.guard_share)
                        } else {
                            Vec::new()
                        };
                        let keep = |i: usize| !drawn.get(i).copied().unwrap_or(false);
                        let slices = bake_slices(&strands, keep, plane_params, Some(&call))?;
                        let summary = format!(
                            "{} planes per axis, slices {}×{}, lean ({:.2}, {:.2})",
                            slices.planes, slices.size[0], slices.size[1], slices.tilt[0], slices.tilt[1]
                        );
                        Ok((slices, summary))
                    },
                )?)
            }
        };

        let depth_in_tiles = params.fur_depth() / params.patches.tile_size;
        let transfer = match &params.transfer {
            None => {
                self.transfer = None;
                None
            }
            Some(choice) => {
                let transfer_key = KeyHasher::new("transfer")
                    .key(coverage_key)
                    .params(choice)
                    .params(&depth_in_tiles)
                    .finish();
                Some(run_stage(
                    &mut self.transfer,
                    transfer_key,
                    "transfer",
                    &mut report,
                    || {
                        let callback = stage_callback(progress, "transfer");
                        let call = |f: f64| callback.as_ref().is_none_or(|c| c(f));
                        let baked = bake_transfer_of(&volume, choice, depth_in_tiles, &call)?;
                        let summary = match &baked.bands {
                            Some(bands) => format!(
                                "order {} by band selection ({} within {:.1}%), {} textures",
                                baked.transfer.order,
                                if bands.met { "met" } else { "not met" },
                                100.0 * bands.tolerance,
                                baked.packed_f16.textures
                            ),
                            None => format!(
                                "order {}, {} textures",
                                baked.transfer.order, baked.packed_f16.textures
                            ),
                        };
                        Ok((baked, summary))
                    },
                )?)
            }
        };

        Ok(FurAsset {
            mesh,
            patches,
            volume,
            guard_hairs,
            planes,
            transfer,
            params: params.clone(),
            report,
        })
    }
}

/// The stage's callback: `progress` with the stage name bound.
fn stage_callback<'a>(
    progress: Option<StageCallback<'a>>,
    stage: &'a str,
) -> Option<impl Fn(f64) -> bool + Sync + 'a> {
    progress.map(|p| move |f: f64| p(stage, f))
}

/// Reuses `slot` when its key is `key`, else runs `work` and caches its result; records the
/// stage in `report` either way.
fn run_stage<T>(
    slot: &mut Option<Cached<T>>,
    key: u64,
    stage: &str,
    report: &mut Vec<StageReport>,
    work: impl FnOnce() -> Result<(T, String)>,
) -> Result<Arc<T>> {
    if let Some(cached) = slot.as_ref().filter(|c| c.key == key) {
        report.push(StageReport {
            stage: stage.into(),
            ran: false,
            seconds: 0.0,
            summary: "inputs unchanged: reused".into(),
        });
        return Ok(cached.value.clone());
    }
    // A failed or cancelled stage must not leave a stale result behind a new key.
    *slot = None;
    let start = Instant::now();
    let (value, summary) = work()?;
    let value = Arc::new(value);
    report.push(StageReport {
        stage: stage.into(),
        ran: true,
        seconds: start.elapsed().as_secs_f64(),
        summary,
    });
    *slot = Some(Cached {
        key,
        value: value.clone(),
    });
    Ok(value)
}

/// The transfer of `volume` with the fur `depth_in_tiles` deep, packed.
fn bake_transfer_of(
    volume: &HairVolume,
    choice: &TransferChoice,
    depth_in_tiles: f64,
    progress: ProgressCallback<'_>,
) -> Result<TransferBake> {
    let input = VolumeInput::new(volume, depth_in_tiles);
    let transfer_volume = input.transfer_volume(volume);
    let (transfer, bands) = if choice.auto {
        let (t, r) = bake_transfer_auto(&transfer_volume, &choice.params, &choice.bands, Some(progress))?;
        (t, Some(r))
    } else {
        (
            bake_transfer(&transfer_volume, &choice.params, Some(progress))?,
            None,
        )
    };
    Ok(TransferBake {
        packed_f16: pack_f16(&transfer)?,
        packed_u8: pack_u8(&transfer)?,
        transfer,
        bands,
        depth_in_tiles,
    })
}
