//! Guard hairs as explicit strands over the shells.
//!
//! The hybrid paper (`hybrid-fur-volume-and-strands`, §1 and §3) gives the dense, thin
//! undercoat to a volume and the coarse guard hairs to explicit tapered strands: shells alone
//! look velvety up close and cut the silhouette hard. Pelt's guard hairs are the tile's overcoat
//! strands ([`Coat::Overcoat`], a share `guard_fraction` of the `density`), placed over the mesh
//! exactly where the shells would show them ([`crate::placement`]); a volume baked with
//! [`VolumeParams::guard_hairs`](crate::volume::VolumeParams::guard_hairs) leaves out the
//! `guard_share` of the overcoat drawn as strands, so every hair is drawn once, in the shells or
//! as a strand, and the two together cover what the full coat covers.

use crate::error::{Num, PeltError, Result};
use crate::hair::{Coat, HairParams, Strand, grow_strands};
use crate::lapped::Patches;
use crate::memory;
use crate::mesh::FurMesh;
use crate::placement::{PlacedStrands, place_strands};

/// Most guard strands one mesh may carry (the hybrid paper's mink pelt has about 20,000 hair
/// strands; a game character a few thousand guard hairs).
pub const MAX_GUARD_STRANDS: usize = 1 << 20;

/// Random stream of the choice of which overcoat strands are drawn as strands.
const SHARE_STREAM: u64 = 0x0067_7561_7264;

/// Per strand of the tile (`grow_strands`' output), whether it is drawn as a guard hair when a
/// `share` of the overcoat is: the `round(share · n)` of the `n` overcoat strands with the lowest
/// draws of their own random stream, so the share holds in every tile exactly and a smaller
/// share draws a subset of a larger one's. The volume leaves out exactly these
/// ([`crate::volume::VolumeParams::guard_share`]).
pub fn drawn_as_strands(strands: &[Strand], share: f64) -> Vec<bool> {
    let mut overcoat: Vec<(f64, usize)> = strands
        .iter()
        .enumerate()
        .filter(|(_, s)| s.coat == Coat::Overcoat)
        .map(|(i, _)| (crate::rng::Rng::stream(0, SHARE_STREAM, i as u64).next_f64(), i))
        .collect();
    let count = (share.clamp(0.0, 1.0) * overcoat.len() as f64).round() as usize;
    overcoat.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let mut drawn = vec![false; strands.len()];
    for &(_, i) in &overcoat[..count] {
        drawn[i] = true;
    }
    drawn
}

/// Bytes per placed point (xyz and radius) and per strand (its span).
const POINT_BYTES: f64 = std::mem::size_of::<[f32; 4]>() as f64;
const STRAND_BYTES: f64 = std::mem::size_of::<crate::placement::StrandSpan>() as f64;

/// The guard hairs of `hair` over `mesh`: the `share` of its overcoat strands that
/// [`drawn_as_strands`] picks, placed through `patches`, `fur_depth` object units tall at length
/// multiplier 1, colored as the shells color them. Bald spots (length 0) carry none.
///
/// # Errors
/// [`PeltError::InvalidParameter`] naming `fur_depth` (not positive and finite),
/// `guard_fraction` (0: no hair would be a guard hair), `guard_share` (outside `(0, 1]`),
/// `overcoat.width` (a base width of 0: a guard hair would not show), a field of `hair`,
/// `patches` (not the mesh's), or `guard_fraction` again when the mesh would carry more than
/// [`MAX_GUARD_STRANDS`];
/// [`PeltError::MemoryLimit`] above the memory limit.
pub fn guard_hairs(
    mesh: &FurMesh,
    patches: &Patches,
    hair: &HairParams,
    fur_depth: f64,
    share: f64,
) -> Result<PlacedStrands> {
    validate(hair, fur_depth, share)?;
    let grown = grow_strands(hair)?;
    let drawn = drawn_as_strands(&grown, share);
    let strands: Vec<_> = grown
        .into_iter()
        .zip(drawn)
        .filter_map(|(s, d)| d.then_some(s))
        .collect();
    place_strands(mesh, patches, &strands, fur_depth as f32, |count, points| {
        if count > MAX_GUARD_STRANDS {
            return Err(PeltError::parameter(
                "guard_fraction",
                format!(
                    "the mesh would carry {count} guard hairs, at most {MAX_GUARD_STRANDS}: lower \
                     `guard_share` ({}), `guard_fraction` ({}) or `density` ({}), or raise \
                     `tile_size`",
                    Num(share),
                    Num(hair.guard_fraction),
                    hair.density
                ),
            ));
        }
        let bytes = POINT_BYTES * points as f64 + STRAND_BYTES * count as f64;
        memory::check("guard_hairs", bytes, || {
            format!(
                "`guard_share` ({}), `guard_fraction` ({}) or `density` ({}), or raise `tile_size`",
                Num(share),
                Num(hair.guard_fraction),
                hair.density
            )
        })
    })
}

/// `Ok` when `share` (of the overcoat drawn as strands) lies in `(0, 1]`.
///
/// # Errors
/// [`PeltError::InvalidParameter`] naming `guard_share`.
pub fn check_share(share: f64) -> Result<()> {
    SHARE.check(share)
}

/// The range of the guard hairs' share (`crate::params`).
pub const SHARE: crate::params::Range =
    crate::params::Range::open_below("guard_share", 0.0, 1.0, "share of the overcoat");

/// Checks what guard hairs need beyond [`HairParams::validate`].
///
/// # Errors
/// As [`guard_hairs`], before anything is grown.
pub fn validate(hair: &HairParams, fur_depth: f64, share: f64) -> Result<()> {
    hair.validate()?;
    check_share(share)?;
    if !(fur_depth.is_finite() && fur_depth > 0.0) {
        return Err(PeltError::parameter(
            "fur_depth",
            format!("must be positive and finite, got {}", Num(fur_depth)),
        ));
    }
    if hair.guard_fraction <= 0.0 {
        return Err(PeltError::parameter(
            "guard_fraction",
            "is 0: no hair would be a guard hair (raise it, or bake without guard hairs)",
        ));
    }
    if hair.overcoat.width[0] <= 0.0 {
        return Err(PeltError::parameter(
            "overcoat.width",
            format!(
                "must start above 0 for guard hairs (a hair of width 0 does not show), got [{}, {}]",
                Num(hair.overcoat.width[0]),
                Num(hair.overcoat.width[1])
            ),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests;
