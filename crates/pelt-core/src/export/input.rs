//! What an export reads: one furred object (mesh, patch UVs, hair volume, optional transfer
//! textures, fur depth), borrowed, checked once before any file is written.
//!
//! The shell stack follows Lengyel et al. 2001, §2.2–§2.3 (layer `i` of `L` at `i · spacing` of
//! the fur depth) and the transfer textures the PRT shell-fur paper, §2.3 (4 coefficients per
//! RGBA texel, float16 or 8-bit with a scale and bias per coefficient).

use crate::FurMesh;
use crate::error::{PeltError, Result};
use crate::mesh::uv_split::validate_uvs;
use crate::placement::PlacedStrands;
use crate::prt::pack::{PackedF16, PackedU8, texture_count};
use crate::prt::sh::MAX_ORDER;
use crate::volume::HairVolume;

use crate::mesh::FUR_DEPTH;

use super::materials::MaterialSlots;
use super::names::validate_name;
pub use super::names::{MAX_NAME_CHARS, file_stem};
use super::rig::{Animation, SkinBinding, Transform};

/// The packed transfer textures of one object (see [`crate::prt::pack`]).
#[derive(Debug, Clone, Copy)]
pub struct TransferTextures<'a> {
    /// SH order n (`n²` coefficients).
    pub order: usize,
    /// Float16 textures, for EXR and KTX2.
    pub f16: &'a PackedF16,
    /// 8-bit textures with their scale and bias, for PNG (glTF images are 8-bit).
    pub u8: &'a PackedU8,
}

/// One furred object to export, borrowed.
#[derive(Debug, Clone, Copy)]
pub struct ExportInput<'a> {
    /// Object name: the glTF node and mesh name and the stem of its texture files. 1 to 64
    /// characters; characters outside `[A-Za-z0-9_.-]` become `_` in file names.
    pub name: &'a str,
    /// The mesh (colors, comb vectors and lengths as painted; white, none and 1 where absent).
    pub mesh: &'a FurMesh,
    /// Per triangle, the tile UV of each corner (the lapped patches' `uv`).
    pub corner_uvs: &'a [[[f32; 2]; 3]],
    /// The baked hair volume.
    pub volume: &'a HairVolume,
    /// The baked transfer, if any.
    pub transfer: Option<TransferTextures<'a>>,
    /// Object units between the skin and the top layer at length 1, [`FUR_DEPTH`].
    pub fur_depth: f64,
    /// Shells baked into geometry (`geometry` mode) and recommended to engines; `None` means every
    /// layer above the skin (`layers − 1`, at least 1).
    pub shells: Option<usize>,
    /// Where the object stands in the scene (the glTF node's transform). For a skinned object
    /// the pose at which the skin was bound: its node stays at the origin and the joints place it.
    pub transform: Transform,
    /// The object's binding to one of the export's skeletons, if it is skinned.
    pub skin: Option<SkinBinding<'a>>,
    /// The object's own animations: its node's transform (as [`ExportInput::transform`]) at each
    /// time, one pose per time. An unskinned object only: a skinned one moves with its joints.
    pub animations: &'a [Animation],
    /// The object's own materials, kept on its bald faces ([`super::materials`]); `None`: every
    /// face is Pelt's skin.
    pub materials: Option<MaterialSlots<'a>>,
    /// The guard hairs over the mesh ([`crate::guard`]), drawn as strands beside the shells.
    pub guard_hairs: Option<&'a PlacedStrands>,
}

/// Most shells drawn (the renderer's and the volume's layer bound).
pub const MAX_SHELLS: usize = crate::volume::bake::MAX_LAYERS;

impl ExportInput<'_> {
    /// Shells to draw: [`ExportInput::shells`] or `layers − 1` (at least 1).
    pub fn shell_count(&self) -> usize {
        self.shells
            .unwrap_or_else(|| self.volume.layers.saturating_sub(1).max(1))
    }

    /// The name with every character outside `[A-Za-z0-9_.-]` replaced by `_`, for file names.
    pub fn file_stem(&self) -> String {
        file_stem(self.name)
    }

    /// Checks the name, the UVs against the mesh, the volume's arrays against its sizes, the
    /// transfer textures against the volume, the fur depth, the shell count, the materials, the
    /// object's animations and the transform (the skin binding is checked against the skeletons
    /// by the glTF export).
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] naming `name`, `corner_uvs`, the `volume.*` array,
    /// `transfer.*`, `fur_depth`, `shells`, `materials.*`, `animations[*]` or `transform`.
    pub fn validate(&self) -> Result<()> {
        validate_name("name", self.name)?;
        validate_uvs(self.mesh, self.corner_uvs)?;
        validate_volume(self.volume)?;
        if let Some(transfer) = &self.transfer {
            validate_transfer(transfer, self.volume)?;
        }
        FUR_DEPTH.check(self.fur_depth)?;
        if let Some(shells) = self.shells
            && !(1..=MAX_SHELLS).contains(&shells)
        {
            return Err(PeltError::parameter(
                "shells",
                format!("must be in 1..={MAX_SHELLS}, got {shells}"),
            ));
        }
        if let Some(materials) = &self.materials {
            materials.validate(self.mesh.face_count())?;
        }
        if !self.animations.is_empty() && self.skin.is_some() {
            return Err(PeltError::parameter(
                "animations",
                "a skinned object moves with its skeleton's animations: give it none of its own",
            ));
        }
        for (a, animation) in self.animations.iter().enumerate() {
            animation.validate(a, 1)?;
        }
        self.transform.validate("transform")
    }
}

fn size_error(name: &str, expected: usize, got: usize) -> PeltError {
    PeltError::parameter(
        format!("volume.{name}"),
        format!("must hold {expected} values for the volume's sizes, got {got}"),
    )
}

/// Checks every array of the volume against its sizes (a volume edited after the bake, or built
/// by hand, must not make a writer index out of bounds).
pub(crate) fn validate_volume(volume: &HairVolume) -> Result<()> {
    let (layers, res) = (volume.layers, volume.resolution);
    if !(1..=crate::volume::bake::MAX_LAYERS).contains(&layers) {
        return Err(PeltError::parameter(
            "volume.layers",
            format!("must be in 1..={}, got {layers}", crate::volume::bake::MAX_LAYERS),
        ));
    }
    if !(1..=crate::volume::bake::MAX_RESOLUTION).contains(&res) {
        return Err(PeltError::parameter(
            "volume.resolution",
            format!(
                "must be in 1..={}, got {res}",
                crate::volume::bake::MAX_RESOLUTION
            ),
        ));
    }
    if !(volume.layer_spacing.is_finite() && volume.layer_spacing > 0.0 && volume.layer_spacing <= 1.0) {
        return Err(PeltError::parameter(
            "volume.layer_spacing",
            format!("must be in (0, 1], got {}", volume.layer_spacing),
        ));
    }
    let texels = layers * res * res;
    for (name, len, expected) in [
        ("shells", volume.shells.len(), 4 * texels),
        ("tangents", volume.tangents.len(), 4 * texels),
        ("coverage", volume.coverage.len(), texels),
    ] {
        if len != expected {
            return Err(size_error(name, expected, len));
        }
    }
    if let Some(i) = volume.coverage.iter().position(|c| !c.is_finite()) {
        return Err(PeltError::parameter(
            format!("volume.coverage[{i}]"),
            format!("must be finite, got {}", volume.coverage[i]),
        ));
    }
    let [fw, fh] = volume.fin_size;
    if !(1..=crate::volume::bake::MAX_FIN_SIZE).contains(&fw)
        || !(1..=crate::volume::bake::MAX_FIN_SIZE).contains(&fh)
    {
        return Err(PeltError::parameter(
            "volume.fin_size",
            format!(
                "each side must be in 1..={}, got {fw} × {fh}",
                crate::volume::bake::MAX_FIN_SIZE
            ),
        ));
    }
    if volume.fin.len() != 4 * fw * fh {
        return Err(size_error("fin", 4 * fw * fh, volume.fin.len()));
    }
    for (k, level) in volume.mips.iter().enumerate() {
        let side = (res >> (k + 1)).max(1);
        if level.len() != 4 * layers * side * side {
            return Err(size_error(
                &format!("mips[{k}]"),
                4 * layers * side * side,
                level.len(),
            ));
        }
    }
    let full = crate::texture::full_mip_count(res, res);
    if volume.mips.len() + 1 > full {
        return Err(PeltError::parameter(
            "volume.mips",
            format!(
                "has {} levels above the base, at most {} for a {res}² base",
                volume.mips.len(),
                full - 1
            ),
        ));
    }
    Ok(())
}

/// Checks the transfer textures against the volume they were baked from.
fn validate_transfer(transfer: &TransferTextures<'_>, volume: &HairVolume) -> Result<()> {
    if !(1..=MAX_ORDER).contains(&transfer.order) {
        return Err(PeltError::parameter(
            "transfer.order",
            format!("must be in 1..={MAX_ORDER}, got {}", transfer.order),
        ));
    }
    let textures = texture_count(transfer.order * transfer.order);
    let voxels = volume.layers * volume.resolution * volume.resolution;
    let f16 = transfer.f16;
    let u8 = transfer.u8;
    for (name, (t, l, r, len)) in [
        (
            "transfer.f16",
            (f16.textures, f16.layers, f16.resolution, f16.texels.len()),
        ),
        (
            "transfer.u8",
            (u8.textures, u8.layers, u8.resolution, u8.texels.len()),
        ),
    ] {
        if (t, l, r) != (textures, volume.layers, volume.resolution) || len != 4 * textures * voxels {
            return Err(PeltError::parameter(
                name,
                format!(
                    "must hold {textures} textures of {} layers of {}² texels (order {} over the \
                     volume), got {t} of {l} of {r}² ({len} values)",
                    volume.layers, volume.resolution, transfer.order
                ),
            ));
        }
    }
    if let Some(i) = f16.texels.iter().position(|v| !v.is_finite()) {
        return Err(PeltError::parameter(
            format!("transfer.f16.texels[{i}]"),
            "must be finite",
        ));
    }
    let sidecar = &u8.sidecar;
    let n = transfer.order * transfer.order;
    if sidecar.scale.len() != n
        || sidecar.bias.len() != n
        || !sidecar.scale.iter().chain(&sidecar.bias).all(|v| v.is_finite())
    {
        return Err(PeltError::parameter(
            "transfer.u8.sidecar",
            format!("must hold {n} finite scales and biases"),
        ));
    }
    Ok(())
}
