//! The fur passes' pipelines, built on first use per lighting model and target format: each pass
//! (`skin.rs`, `fins.rs`, `shells.rs`, `strands.rs`) builds its own from the shared layouts
//! (`layouts.rs`) and the recipe in `pass.rs`; the occluders' pass (`occluders.rs`), drawn first
//! when the fur is composited into another picture, the copy of a CPU adapter's frame into a
//! caller's texture (`resolve.rs`) and the body's shadow map (`shadow_map.rs`) have their own
//! layouts.

use std::sync::OnceLock;

use super::fins::FinsPass;
use super::layouts::{FurLayouts, validated};
use super::occluders::OccluderPass;
use super::pass::{Model, Target};
use super::resolve::ResolvePass;
use super::shadow_map::ShadowPass;
use super::shells::ShellsPass;
use super::skin::SkinPass;
use super::strands::StrandsPass;
use pelt_core::error::Result;

/// The passes' pipelines for one lighting model and target.
pub(super) struct PassPipelines {
    pub skin: SkinPass,
    pub fins: FinsPass,
    pub shells: ShellsPass,
    pub strands: StrandsPass,
}

/// The layouts and the pipelines built so far; one per [`super::Renderer`].
pub(super) struct FurPipelines {
    pub layouts: FurLayouts,
    /// Indexed by [`variant`].
    passes: [OnceLock<PassPipelines>; 8],
    /// Indexed by the target ([`variant`] under Kajiya–Kay).
    occluders: [OnceLock<OccluderPass>; 4],
    /// Indexed by the target ([`variant`] under Kajiya–Kay).
    resolve: [OnceLock<ResolvePass>; 4],
    shadow: OnceLock<ShadowPass>,
}

fn variant(model: Model, target: Target) -> usize {
    let target = match target {
        Target::Srgb8 => 0,
        Target::Bgra8Srgb => 1,
        Target::Linear16 => 2,
        Target::Linear32 => 3,
    };
    4 * usize::from(model == Model::Prt) + target
}

impl FurPipelines {
    /// Creates the layouts and samplers; pipelines follow on first use.
    ///
    /// # Errors
    /// [`pelt_core::PeltError::Render`] when the device rejects them.
    pub fn new(device: &wgpu::Device) -> Result<Self> {
        Ok(FurPipelines {
            layouts: FurLayouts::new(device)?,
            passes: Default::default(),
            occluders: Default::default(),
            resolve: Default::default(),
            shadow: OnceLock::new(),
        })
    }

    /// The pipelines of `model` into `target`, built on first use.
    ///
    /// # Errors
    /// [`PeltError::Render`] when the device rejects a shader or pipeline (a bug, or a device
    /// missing a downlevel capability).
    pub fn passes(&self, device: &wgpu::Device, model: Model, target: Target) -> Result<&PassPipelines> {
        let slot = &self.passes[variant(model, target)];
        if let Some(p) = slot.get() {
            return Ok(p);
        }
        let (layout, strand_layout) = match model {
            Model::KajiyaKay => (&self.layouts.pipeline_layout, &self.layouts.strand_layout),
            Model::Prt => {
                let prt = self.layouts.prt(device)?;
                (&prt.pipeline_layout, &prt.strand_layout)
            }
        };
        let format = target.format();
        let built = validated(device, "the fur pipelines", || {
            Ok(PassPipelines {
                skin: SkinPass::new(device, layout, model, format)?,
                fins: FinsPass::new(device, layout, model, format)?,
                shells: ShellsPass::new(device, layout, model, format)?,
                strands: StrandsPass::new(device, strand_layout, model, format)?,
            })
        })?;
        Ok(slot.get_or_init(|| built))
    }

    /// The pass writing another renderer's depth into `target`'s frames, built on first use.
    ///
    /// # Errors
    /// [`pelt_core::PeltError::Render`] when the device rejects it.
    pub fn occluders(&self, device: &wgpu::Device, target: Target) -> Result<&OccluderPass> {
        let slot = &self.occluders[variant(Model::KajiyaKay, target)];
        if let Some(p) = slot.get() {
            return Ok(p);
        }
        let built = validated(device, "the occluders' pipeline", || {
            Ok(OccluderPass::new(device, target.format()))
        })?;
        Ok(slot.get_or_init(|| built))
    }

    /// The pass copying a single-float frame into a texture of `target`'s format, built on
    /// first use.
    ///
    /// # Errors
    /// [`pelt_core::PeltError::Render`] when the device rejects it.
    pub fn resolve(&self, device: &wgpu::Device, target: Target) -> Result<&ResolvePass> {
        let slot = &self.resolve[variant(Model::KajiyaKay, target)];
        if let Some(p) = slot.get() {
            return Ok(p);
        }
        let built = validated(device, "the resolve pipeline", || {
            Ok(ResolvePass::new(device, target))
        })?;
        Ok(slot.get_or_init(|| built))
    }

    /// The pass drawing the body's shadow map, built on first use.
    ///
    /// # Errors
    /// [`pelt_core::PeltError::Render`] when the device rejects it.
    pub fn shadow(&self, device: &wgpu::Device) -> Result<&ShadowPass> {
        if let Some(p) = self.shadow.get() {
            return Ok(p);
        }
        let built = validated(device, "the body shadow's pipeline", || {
            Ok(ShadowPass::new(device))
        })?;
        Ok(self.shadow.get_or_init(|| built))
    }
}
