//! Lapped patches: the mesh cut into patches along mesh edges, each with a local texture
//! parameterization whose u axis follows the comb field and whose scale is one tile per
//! `tile_size` world units.
//!
//! This is the geometry preprocessing of Lengyel, Praun, Finkelstein and Hoppe, "Real-Time Fur
//! over Arbitrary Surfaces" (I3D 2001), §2.1: the lapped textures of Praun, Finkelstein and
//! Hoppe (SIGGRAPH 2000) grown over random uncovered places and parameterized by a fast
//! least-squares fit to the tangent field, in the non-overlapping variant where every face lies
//! in exactly one patch and the texture is a toroidal tile (so UVs may leave `[0, 1]`, and each
//! patch gets a random offset in the tile). The jobs are split by file:
//!
//! - `faces`: per-face frames along the field, growth units (whole polygons), adjacency;
//! - `growth`: seeds, growth by whole units, the distortion limits that stop a patch;
//! - `parameterization`: the per-patch least-squares (Poisson) fit and its fast local step;
//! - `merge`: small patches left between big ones join a neighbour where it extends over them;
//! - `quality`: per-face alignment and stretch, seams, coverage;
//! - `picture`: a CPU picture of a layout (patch colors, hair direction) for demos.
//!
//! Alignment is judged with the field's confidence (its strength before normalization): near a
//! singularity the direction turns faster than any patch can follow, so there misalignment
//! counts less and the fit keeps scale instead (see `faces`). The reported figures do not
//! discount anything.
//!
//! Faces whose three vertices all have hair length 0 are bald: they get no patch (id
//! [`NO_PATCH`], UVs 0) and cost nothing.

mod faces;
mod growth;
mod merge;
mod parameterization;
mod picture;
mod quality;

pub use picture::{MAX_SIDE, PictureParams, picture};
pub use quality::{PatchQuality, STRETCH_WITHIN};

use glam::Vec3;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::error::{PeltError, Result};
use crate::field::{self, FieldParams, Singularity};
use crate::mesh::FurMesh;
use crate::params::Range;
use crate::progress::{Progress, ProgressCallback};
use crate::rng::Rng;
use crate::threads::pool;

/// Patch id of a bald face.
pub const NO_PATCH: u32 = u32::MAX;
/// Random stream of the per-patch tile offsets.
const STREAM_OFFSET: u64 = 3;

/// Parameters of [`build_patches`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct PatchParams {
    /// World units covered by one tile of the hair texture; finite, > 0.
    pub tile_size: f64,
    /// Seed of the seed order, the boundary jitter and the tile offsets; any value.
    pub seed: u64,
    /// A patch stops growing before its area-weighted mean alignment error (angle between the
    /// field and the texture's u axis on the surface) exceeds this, degrees; `[0.1, 45]`.
    pub max_alignment_deg: f64,
    /// No face of a patch is misaligned by more than this, degrees, `[max_alignment_deg, 180]`;
    /// the error is scaled by the field's confidence first (see the module docs), so faces
    /// around a singularity are held to it only loosely.
    pub max_face_alignment_deg: f64,
    /// Faces whose Jacobian has a singular value outside `[1/s, s]` count as stretched; `s` in
    /// `[1.01, 4]`.
    pub stretch_tolerance: f64,
    /// A patch stops growing before more than this share of its area is stretched; `[0, 1]`.
    pub max_stretched_fraction: f64,
    /// No face of a grown patch has a singular value outside `[1/m, m]`; `m` in
    /// `[stretch_tolerance, 16]`.
    pub max_stretch: f64,
    /// Most faces in one patch, `[1, 2^24]`: a bound on the cost of each patch's solves.
    pub max_patch_faces: usize,
    /// The direction field the patches follow.
    pub field: FieldParams,
}

impl Default for PatchParams {
    /// A 1-unit tile; limits that keep the whole mesh within the acceptance figures (mean
    /// alignment ≤ 3°, ≥ 95% of the area within `[0.8, 1.25]`) with a margin.
    fn default() -> Self {
        PatchParams {
            tile_size: 1.0,
            seed: 1,
            max_alignment_deg: 2.5,
            max_face_alignment_deg: 30.0,
            stretch_tolerance: 1.25,
            max_stretched_fraction: 0.03,
            max_stretch: 2.0,
            max_patch_faces: 4096,
            field: FieldParams::default(),
        }
    }
}

impl PatchParams {
    /// Checks every field against its documented range.
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] naming the first field out of range.
    pub fn validate(&self) -> Result<()> {
        use ranges::*;
        TILE_SIZE.check(self.tile_size)?;
        MAX_ALIGNMENT_DEG.check(self.max_alignment_deg)?;
        MAX_FACE_ALIGNMENT_DEG.check_above(self.max_face_alignment_deg, self.max_alignment_deg)?;
        STRETCH_TOLERANCE.check(self.stretch_tolerance)?;
        MAX_STRETCHED_FRACTION.check(self.max_stretched_fraction)?;
        MAX_STRETCH.check_above(self.max_stretch, self.stretch_tolerance)?;
        MAX_PATCH_FACES.check(self.max_patch_faces as f64)?;
        self.field.validate()
    }

    /// Each number's range (`crate::params`); the comb field's are [`FieldParams::RANGES`].
    pub const RANGES: &'static [Range] = {
        use ranges::*;
        &[
            TILE_SIZE,
            MAX_ALIGNMENT_DEG,
            MAX_FACE_ALIGNMENT_DEG,
            STRETCH_TOLERANCE,
            MAX_STRETCHED_FRACTION,
            MAX_STRETCH,
            MAX_PATCH_FACES,
        ]
    };
}

/// The ranges of [`PatchParams`]' numbers.
mod ranges {
    use crate::params::Range;

    pub const TILE_SIZE: Range = Range::open_below("tile_size", 0.0, f64::MAX, "object units");
    pub const MAX_ALIGNMENT_DEG: Range = Range::closed("max_alignment_deg", 0.1, 45.0, "degrees");
    pub const MAX_FACE_ALIGNMENT_DEG: Range =
        Range::above_field("max_face_alignment_deg", &MAX_ALIGNMENT_DEG, 180.0, "degrees");
    pub const STRETCH_TOLERANCE: Range = Range::closed("stretch_tolerance", 1.01, 4.0, "stretch ratio");
    pub const MAX_STRETCHED_FRACTION: Range =
        Range::closed("max_stretched_fraction", 0.0, 1.0, "share of faces");
    pub const MAX_STRETCH: Range =
        Range::above_field("max_stretch", &STRETCH_TOLERANCE, 16.0, "stretch ratio");
    pub const MAX_PATCH_FACES: Range = Range::closed("max_patch_faces", 1.0, (1u32 << 24) as f64, "faces");
}

/// A patch layout and the field it follows.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Patches {
    /// Per triangle, the UV of each corner in tile units (the tile repeats; 0 for bald faces).
    pub uv: Vec<[[f32; 2]; 3]>,
    /// Per triangle, its patch, or [`NO_PATCH`] for a bald face.
    pub patch: Vec<u32>,
    /// Per vertex, the unit hair direction (object space, tangent).
    pub direction: Vec<[f32; 3]>,
    /// Per vertex, the hair's angle from the normal, radians.
    pub slant: Vec<f32>,
    /// Singular faces of the direction field.
    pub singularities: Vec<Singularity>,
    /// Figures of the layout.
    pub quality: PatchQuality,
}

/// Builds the direction field of `mesh` and covers its furred faces with patches.
///
/// Runs in Pelt's thread pool; the result depends on `params.seed` but not on the thread count.
///
/// # Errors
/// [`PeltError::InvalidParameter`] when `params` is out of range.
pub fn build_patches(mesh: &FurMesh, params: &PatchParams) -> Result<Patches> {
    build_patches_with_progress(mesh, params, None)
}

/// [`build_patches`] reporting the covered share of the furred faces to `callback`, which may
/// cancel by returning `false`.
///
/// # Errors
/// [`PeltError::InvalidParameter`] when `params` is out of range; [`PeltError::Cancelled`] when
/// the callback cancelled.
pub fn build_patches_with_progress(
    mesh: &FurMesh,
    params: &PatchParams,
    callback: Option<ProgressCallback<'_>>,
) -> Result<Patches> {
    params.validate()?;
    check_tiles_across(mesh, params.tile_size)?;
    pool().install(|| build(mesh, params, callback))
}

/// Most tiles across a mesh: the patch UVs are f32, whose spacing at 2²⁰ tiles is 1/16 of a tile
/// (8 texels of a 128² tile); beyond, the texture cannot be placed (and at 2¹²⁸ the UVs are inf).
pub const MAX_TILES_ACROSS: f64 = (1u64 << 20) as f64;

/// Fewest tiles across a mesh: a mesh 2⁻²⁰ tiles across spans 16 f32 steps of a UV near 1; a
/// smaller one would collapse onto a point of the texture (zero UV areas, NaN figures).
pub const MIN_TILES_ACROSS: f64 = 1.0 / (1u64 << 20) as f64;

/// Refuses a `tile_size` so small or so large against the mesh that f32 UVs cannot place the
/// tiles or tell the mesh's corners apart.
fn check_tiles_across(mesh: &FurMesh, tile_size: f64) -> Result<()> {
    let stats = mesh.stats();
    let length = Vec3::from(stats.bbox_max)
        .as_dvec3()
        .distance(Vec3::from(stats.bbox_min).as_dvec3());
    let tiles = length / tile_size;
    if (MIN_TILES_ACROSS..=MAX_TILES_ACROSS).contains(&tiles) || length == 0.0 {
        return Ok(());
    }
    Err(PeltError::parameter(
        "tile_size",
        format!(
            "must be in [{:e}, {:e}] for this mesh (2⁻²⁰ to 2²⁰ tiles across its bounding-box \
             diagonal of {length:e}, what float32 UVs can place), got {tile_size:e} ({tiles:e} \
             tiles across)",
            length / MAX_TILES_ACROSS,
            length / MIN_TILES_ACROSS,
        ),
    ))
}

/// [`build_patches_with_progress`] without validation or pool.
pub(crate) fn build(
    mesh: &FurMesh,
    params: &PatchParams,
    callback: Option<ProgressCallback<'_>>,
) -> Result<Patches> {
    let field = field::build(mesh, &params.field);
    let bald = bald_faces(mesh);
    let units = faces::Units::build(mesh, &bald);
    let frames = faces::frames(mesh, &field.direction, &field.strength, &units);
    let furred = bald.iter().filter(|&&b| !b).count();
    let progress = Progress::new(furred, callback);
    let limits = growth::Limits {
        mean_alignment: params.max_alignment_deg.to_radians(),
        face_alignment: params.max_face_alignment_deg.to_radians(),
        stretch: params.stretch_tolerance,
        stretched_share: params.max_stretched_fraction,
        max_stretch: params.max_stretch,
        max_faces: params.max_patch_faces,
    };
    let mut grown = growth::grow(mesh, &frames, &units, limits, params.seed, &progress)?;
    let count = grown.origin.len();
    merge::merge_small(mesh, &frames, &limits, &mut grown.patch, &mut grown.uv, count);
    grown.compact();
    let offsets: Vec<[f64; 2]> = (0..grown.origin.len() as u64)
        .map(|p| {
            let mut rng = Rng::stream(params.seed, STREAM_OFFSET, p);
            [rng.next_f64(), rng.next_f64()]
        })
        .collect();
    let uv: Vec<[[f32; 2]; 3]> = (0..mesh.face_count())
        .into_par_iter()
        .map(|f| {
            let p = grown.patch[f];
            if p == NO_PATCH {
                return [[0.0; 2]; 3];
            }
            let (origin, offset) = (grown.origin[p as usize], offsets[p as usize]);
            grown.uv[f].map(|c| [0, 1].map(|k| ((c[k] - origin[k]) / params.tile_size + offset[k]) as f32))
        })
        .collect();
    let quality = quality::measure(
        mesh,
        &frames,
        &bald,
        &uv,
        &grown.patch,
        params.tile_size,
        grown.origin.len(),
        field.singularities.len(),
    );
    Ok(Patches {
        uv,
        patch: grown.patch,
        direction: field.direction,
        slant: field.slant,
        singularities: field.singularities,
        quality,
    })
}

/// Faces whose three vertices all have hair length 0.
fn bald_faces(mesh: &FurMesh) -> Vec<bool> {
    match mesh.length() {
        None => vec![false; mesh.face_count()],
        Some(length) => mesh
            .triangles()
            .par_iter()
            .map(|t| t.iter().all(|&v| length[v as usize] == 0.0))
            .collect(),
    }
}

#[cfg(test)]
mod tests;
