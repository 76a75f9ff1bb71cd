//! The fur as explicit geometry in object space: every strand of the tile, instantiated wherever
//! the lapped patches place its root ([`crate::placement`], the map the shells are lifted by),
//! plus the skin it grows from.

use glam::{Vec3, Vec3A};

use crate::error::{Num, PeltError, Result};
use crate::hair::Strand;
use crate::lapped::Patches;
use crate::mesh::FurMesh;
use crate::placement::place_strands;
pub(crate) use crate::placement::{StrandSpan, growth_vectors, lateral_scale};

/// Most strand points the reference holds (about 1 GiB of points): above it the asset is
/// refused before anything is allocated.
pub const MAX_POINTS: usize = 1 << 26;

/// One strand in object space.
#[derive(Debug, Clone, PartialEq)]
pub struct WorldStrand {
    /// Polyline points, root first; at least two.
    pub points: Vec<[f32; 3]>,
    /// Radius at each point, object units, finite and non-negative.
    pub radii: Vec<f32>,
    /// Linear albedo at the root.
    pub root_color: [f32; 3],
    /// Linear albedo at the tip; the albedo is linear in the point index in between.
    pub tip_color: [f32; 3],
}

/// The opaque skin under the hair: triangles with smooth normals and a per-vertex albedo.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Skin {
    pub positions: Vec<Vec3A>,
    pub normals: Vec<Vec3A>,
    pub albedo: Vec<Vec3>,
    pub triangles: Vec<[u32; 3]>,
}

/// The skin at a point of one of its triangles, facing the viewer.
#[derive(Debug, Clone, Copy)]
pub(crate) struct SkinPoint {
    /// Smooth unit normal.
    pub normal: Vec3A,
    /// Unit normal of the triangle's plane.
    pub face: Vec3A,
    pub albedo: Vec3,
}

impl Skin {
    /// Triangle `triangle` at barycentric weights `w`, both normals turned toward `view`.
    pub(crate) fn at(&self, triangle: u32, w: Vec3, view: Vec3A) -> SkinPoint {
        let t = self.triangles[triangle as usize].map(|v| v as usize);
        let p = t.map(|v| self.positions[v]);
        let face = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
        let normal = (0..3)
            .fold(Vec3A::ZERO, |s, k| s + w[k] * self.normals[t[k]])
            .normalize_or(face);
        let albedo = (0..3).fold(Vec3::ZERO, |s, k| s + w[k] * self.albedo[t[k]]);
        let sign = if face.dot(view) < 0.0 { -1.0 } else { 1.0 };
        SkinPoint {
            normal: sign * normal,
            face: sign * face,
            albedo,
        }
    }
}

/// Strands and skin in object space, ready for [`super::ReferenceScene::new`].
#[derive(Debug, Clone, PartialEq)]
pub struct FurGeometry {
    /// Every strand point: xyz and radius.
    pub(crate) points: Vec<[f32; 4]>,
    pub(crate) strands: Vec<StrandSpan>,
    pub(crate) skin: Option<Skin>,
}

impl FurGeometry {
    /// Strands given in object space, without a skin (for tests and hand-made scenes).
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] for a strand with fewer than two points, radii that do
    /// not match its points, or a value that is not finite (named `strands[i]`).
    pub fn from_world_strands(strands: &[WorldStrand]) -> Result<Self> {
        let total: usize = strands.iter().map(|s| s.points.len()).sum();
        check_points(total)?;
        let mut points = Vec::with_capacity(total);
        let mut spans = Vec::with_capacity(strands.len());
        for (i, s) in strands.iter().enumerate() {
            let name = format!("strands[{i}]");
            if s.points.len() < 2 || s.radii.len() != s.points.len() {
                return Err(PeltError::parameter(
                    name,
                    format!(
                        "needs at least two points and one radius per point, got {} points and {} radii",
                        s.points.len(),
                        s.radii.len()
                    ),
                ));
            }
            let finite = s.points.iter().flatten().all(|v| v.is_finite())
                && s.radii.iter().all(|r| r.is_finite() && *r >= 0.0)
                && s.root_color.iter().chain(&s.tip_color).all(|c| c.is_finite());
            if !finite {
                return Err(PeltError::parameter(
                    name,
                    "points, colors must be finite and radii finite and non-negative",
                ));
            }
            spans.push(StrandSpan {
                first: points.len() as u32,
                count: s.points.len() as u32,
                root_color: Vec3::from(s.root_color),
                tip_color: Vec3::from(s.tip_color),
                triangle: crate::placement::NO_TRIANGLE,
                weights: [0.0; 3],
            });
            points.extend(s.points.iter().zip(&s.radii).map(|(p, &r)| [p[0], p[1], p[2], r]));
        }
        Ok(FurGeometry {
            points,
            strands: spans,
            skin: None,
        })
    }

    /// The fur of a bake: `strands` (the tile's, from `grow_strands` with the bake's
    /// `HairParams`) placed over `mesh` through the `patches`' corner UVs, `fur_depth` object
    /// units tall at length multiplier 1, colored by the strand's colors times the mesh's
    /// `pelt_color` at the root; and the skin, whose albedo is the strands' mean root color
    /// times `pelt_color` (the shells' opaque layer 0).
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] when `fur_depth` is not positive and finite, the patches
    /// do not belong to the mesh, or the fur would need more than [`MAX_POINTS`] points.
    pub fn from_bake(mesh: &FurMesh, patches: &Patches, strands: &[Strand], fur_depth: f64) -> Result<Self> {
        if !(fur_depth.is_finite() && fur_depth > 0.0) {
            return Err(PeltError::parameter(
                "fur_depth",
                format!("must be positive and finite, got {}", Num(fur_depth)),
            ));
        }
        let placed = place_strands(mesh, patches, strands, fur_depth as f32, |_, points| {
            check_points(points)
        })?;
        let mean_root = mean_root_color(strands);
        Ok(FurGeometry {
            points: placed.points,
            strands: placed.spans,
            skin: Some(skin_of(mesh, mean_root)),
        })
    }

    /// Number of strands.
    pub fn strand_count(&self) -> usize {
        self.strands.len()
    }

    /// Number of strand points.
    pub fn point_count(&self) -> usize {
        self.points.len()
    }

    /// Whether the skin is part of the geometry.
    pub fn has_skin(&self) -> bool {
        self.skin.is_some()
    }
}

fn check_points(total: usize) -> Result<()> {
    if total > MAX_POINTS {
        return Err(PeltError::parameter(
            "strands",
            format!(
                "the fur would need {total} strand points, the reference holds at most {MAX_POINTS}: \
                 lower the hair density or raise the tile size"
            ),
        ));
    }
    Ok(())
}

pub(crate) fn mean_root_color(strands: &[Strand]) -> Vec3 {
    if strands.is_empty() {
        return Vec3::ZERO;
    }
    let sum = strands
        .iter()
        .fold(glam::DVec3::ZERO, |s, k| s + Vec3::from(k.root_color).as_dvec3());
    (sum / strands.len() as f64).as_vec3()
}

/// The skin of `mesh`: its albedo the strands' mean root color `mean_root` times `pelt_color`
/// (the shells' opaque layer 0).
pub(crate) fn skin_of(mesh: &FurMesh, mean_root: Vec3) -> Skin {
    let albedo = (0..mesh.vertex_count())
        .map(|v| {
            let c = mesh.color().map_or([1.0; 4], |c| c[v]);
            mean_root * Vec3::new(c[0], c[1], c[2])
        })
        .collect();
    Skin {
        positions: mesh.positions().iter().map(|&p| Vec3A::from(p)).collect(),
        normals: mesh.normals().iter().map(|&n| Vec3A::from(n)).collect(),
        albedo,
        triangles: mesh.triangles().to_vec(),
    }
}
