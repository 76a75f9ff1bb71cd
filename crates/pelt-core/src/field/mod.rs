//! Comb vectors → a smooth unit tangent direction field per vertex.
//!
//! Lengyel et al. 2001 (§3, "Hair direction") store a comb vector `c_v` per vertex whose
//! tangential part is the hair direction, and build the lapped patches along a global direction
//! field (§2.1). This module turns the painted combs into that field. It follows Knöppel,
//! Crane, Pinkall and Schröder, "Globally Optimal Direction Fields" (SIGGRAPH 2013) for n = 1
//! with soft constraints: one complex number per vertex in its tangent frame, and the field
//! minimizing
//!
//! ```text
//! Σ_edges w_ij |z_j - r_ij z_i|²  +  Σ_painted κ d_i |z_i - q_i|²  +  Σ_unpainted (A_i / ℓ²) |z_i - p_i|²
//! ```
//!
//! (cotangent weights `w`, transport `r`, vertex degree `d_i = Σ_j w_ij`, unit painted
//! directions `q`, vertex areas `A`, the default `p` = "down" projected into the tangent plane,
//! blend length `ℓ`), a sparse Hermitian positive definite system solved by preconditioned
//! conjugate gradients. Painted combs hold to about `1/κ` of the turn between neighbours; away
//! from them the field relaxes to "down" over the length `ℓ`; where "down" is normal to the
//! surface (`p` ≈ 0) the field is free and the singularities the hairy ball theorem demands
//! settle there, away from the painted combs that pin `|z|` near 1. Each connected component is
//! its own block of the system with its own `ℓ`. Where "down" flips across a horizontal ridge
//! (the top of a torus) the linear solution passes through zero rather than turning, which
//! normalizes to a parting: hair falls to either side, as it would.
//!
//! The slant (the comb's angle from the normal) blends the same way through the scalar version
//! of the system: painted values held, 0 (upright) far from any paint.

mod connection;
mod singularities;

pub use singularities::Singularity;

use serde::{Deserialize, Serialize};

use crate::cg;
use crate::error::{PeltError, Result};
use crate::mesh::{FurMesh, NO_COMPONENT, orthonormal_basis};
use crate::params::Range;
use crate::threads::pool;
use connection::{Connection, wide};

/// A comb shorter than this share of the longest comb counts as unset.
const TINY_COMB: f64 = 1e-6;
/// A comb whose tangential part is shorter than this share of its length (within about 0.06° of
/// the normal) counts as unset: it has no direction.
const NORMAL_PARALLEL: f64 = 1e-3;
/// Weight of the tie-breaking direction where "down" is normal to a whole region (a flat floor).
const SECONDARY_WEIGHT: f64 = 1e-3;
/// Relative residual at which the solves stop.
const TOLERANCE: f64 = 1e-5;
/// Iteration cap of the solves (never reached on the test meshes; the result stays finite).
const MAX_ITERATIONS: usize = 20_000;

/// Parameters of [`comb_field`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct FieldParams {
    /// Object-space direction hair falls towards where nothing is painted; finite, nonzero.
    pub down: [f32; 3],
    /// Length over which the field relaxes from painted combs to "down", as a share of the square
    /// root of the component's area; `[1e-3, 10]`.
    pub blend: f64,
    /// How firmly painted combs hold (`κ`): their weight relative to the smoothness weight of the
    /// vertex; `[1, 1e6]`.
    pub comb_weight: f64,
}

impl Default for FieldParams {
    fn default() -> Self {
        FieldParams {
            down: [0.0, 0.0, -1.0],
            blend: 0.05,
            comb_weight: 100.0,
        }
    }
}

impl FieldParams {
    /// Checks every field against its documented range.
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] naming the first field out of range.
    pub fn validate(&self) -> Result<()> {
        let d = wide(self.down);
        if !d.is_finite() || d.length_squared() == 0.0 {
            return Err(PeltError::parameter(
                "down",
                format!("must be a finite nonzero vector, got {:?}", self.down),
            ));
        }
        ranges::BLEND.check(self.blend)?;
        ranges::COMB_WEIGHT.check(self.comb_weight)
    }

    /// Each number's range (`crate::params`); `down` is any finite nonzero vector.
    pub const RANGES: &'static [Range] = &[ranges::BLEND, ranges::COMB_WEIGHT];
}

/// The ranges of [`FieldParams`]' numbers.
mod ranges {
    use crate::params::Range;

    pub const BLEND: Range = Range::closed("blend", 1e-3, 10.0, "share of √(component area)");
    pub const COMB_WEIGHT: Range = Range::closed("comb_weight", 1.0, 1e6, "weight");
}

/// The direction field of a mesh.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DirectionField {
    /// Unit hair direction per vertex, object space, orthogonal to the vertex normal.
    pub direction: Vec<[f32; 3]>,
    /// Angle of the hair from the normal per vertex, radians in `[0, π/2]` (painted combs' own
    /// slant, blending to 0 away from them).
    pub slant: Vec<f32>,
    /// Magnitude of the smoothest field before normalization, in `[0, 1]`-ish: near 1 where the
    /// direction is well defined, near 0 around singularities.
    pub strength: Vec<f32>,
    /// Per vertex: whether its comb was set (long enough and not parallel to the normal).
    pub painted: Vec<bool>,
    /// Faces around which the field turns (sum of indices = Euler characteristic per closed
    /// component).
    pub singularities: Vec<Singularity>,
}

/// Builds the direction field of `mesh` from its comb vectors (all unset when it has none).
///
/// Runs in Pelt's thread pool; the result does not depend on the thread count.
///
/// # Errors
/// [`PeltError::InvalidParameter`] when `params` is out of range.
pub fn comb_field(mesh: &FurMesh, params: &FieldParams) -> Result<DirectionField> {
    params.validate()?;
    Ok(pool().install(|| build(mesh, params)))
}

/// [`comb_field`] without validation or pool (callers inside the pool, tests with their own).
pub(crate) fn build(mesh: &FurMesh, params: &FieldParams) -> DirectionField {
    let n = mesh.vertex_count();
    let combs = read_combs(mesh);
    let prior = default_directions(mesh, params.down);
    let connection = Connection::build(mesh);
    let components = mesh.topology().vertex_components();
    let (area, component_area) = vertex_areas(mesh, &components);

    // Diagonal weights and targets of the soft constraints.
    let mut shift = vec![0.0; n];
    let mut rhs = vec![0.0; 2 * n];
    let mut slant_rhs = vec![0.0; 2 * n];
    for i in 0..n {
        let degree = connection.degree[i];
        let (weight, target) = match combs[i] {
            Some((q, slant)) => {
                let weight = if degree > 0.0 {
                    params.comb_weight * degree
                } else {
                    1.0
                };
                slant_rhs[2 * i] = weight * slant;
                (weight, q)
            }
            None => {
                let c = components[i];
                let total = if c == NO_COMPONENT {
                    0.0
                } else {
                    component_area[c as usize]
                };
                let weight = if total > 0.0 && degree > 0.0 {
                    area[i] / (params.blend * params.blend * total)
                } else {
                    // A loose vertex or an all-degenerate component: just take the default.
                    1.0
                };
                (weight, prior[i])
            }
        };
        shift[i] = weight;
        rhs[2 * i] = weight * target[0];
        rhs[2 * i + 1] = weight * target[1];
    }
    let inv_diag: Vec<f64> = (0..2 * n)
        .map(|k| {
            let d = connection.degree[k / 2] + shift[k / 2];
            if d > 0.0 { 1.0 / d } else { 0.0 }
        })
        .collect();

    // Start from the targets: already right wherever the constraints dominate.
    let mut z = vec![0.0; 2 * n];
    for i in 0..n {
        let target = combs[i].map_or(prior[i], |(q, _)| q);
        z[2 * i] = target[0];
        z[2 * i + 1] = target[1];
    }
    cg::solve(
        |x, y| connection.apply(&shift, false, x, y),
        &inv_diag,
        &rhs,
        &mut z,
        TOLERANCE,
        MAX_ITERATIONS,
    );

    let painted: Vec<bool> = combs.iter().map(Option::is_some).collect();
    let slant = if painted.contains(&true) {
        let mut s = vec![0.0; 2 * n];
        cg::solve(
            |x, y| connection.apply(&shift, true, x, y),
            &inv_diag,
            &slant_rhs,
            &mut s,
            TOLERANCE,
            MAX_ITERATIONS,
        );
        (0..n)
            .map(|i| s[2 * i].clamp(0.0, std::f64::consts::FRAC_PI_2) as f32)
            .collect()
    } else {
        vec![0.0; n]
    };

    let mut unit = vec![[1.0, 0.0]; n];
    let mut strength = vec![0.0f32; n];
    let mut direction = vec![[0.0f32; 3]; n];
    for i in 0..n {
        let zi = [z[2 * i], z[2 * i + 1]];
        let m = zi[0].hypot(zi[1]);
        let u = if m > 1e-12 && m.is_finite() {
            [zi[0] / m, zi[1] / m]
        } else {
            // Exactly singular vertex: fall back to the default (or the frame's tangent).
            let p = prior[i];
            let pm = p[0].hypot(p[1]);
            if pm > 0.0 {
                [p[0] / pm, p[1] / pm]
            } else {
                [1.0, 0.0]
            }
        };
        unit[i] = u;
        strength[i] = if m.is_finite() { m as f32 } else { 0.0 };
        let (t, b) = (wide(mesh.tangents()[i]), wide(mesh.bitangents()[i]));
        direction[i] = [0, 1, 2].map(|k| (u[0] * t[k] + u[1] * b[k]) as f32);
    }
    let singularities = singularities::find(mesh, &unit, &connection.transport);
    DirectionField {
        direction,
        slant,
        strength,
        painted,
        singularities,
    }
}

/// Per vertex: the painted unit direction in the vertex frame and its slant, or `None`.
fn read_combs(mesh: &FurMesh) -> Vec<Option<([f64; 2], f64)>> {
    let n = mesh.vertex_count();
    let Some(combs) = mesh.comb() else {
        return vec![None; n];
    };
    let longest = combs.iter().map(|&c| wide(c).length()).fold(0.0, f64::max);
    (0..n)
        .map(|i| {
            let c = wide(combs[i]);
            let length = c.length();
            if length == 0.0 || length <= TINY_COMB * longest {
                return None;
            }
            let normal = wide(mesh.normals()[i]);
            let along = c.dot(normal);
            let (x, y) = (c.dot(wide(mesh.tangents()[i])), c.dot(wide(mesh.bitangents()[i])));
            let tangential = x.hypot(y);
            if tangential <= NORMAL_PARALLEL * length {
                return None;
            }
            let slant = tangential.atan2(along).min(std::f64::consts::FRAC_PI_2);
            Some(([x / tangential, y / tangential], slant))
        })
        .collect()
}

/// "Down" projected into each tangent plane (not normalized: it fades where down is normal to
/// the surface), plus a faint second direction so that a region facing straight up or down still
/// has a preferred direction.
fn default_directions(mesh: &FurMesh, down: [f32; 3]) -> Vec<[f64; 2]> {
    let d = wide(down);
    let length = d.length();
    let d = d / length;
    let secondary = wide(orthonormal_basis(down.map(|c| (f64::from(c) / length) as f32))[1]);
    (0..mesh.vertex_count())
        .map(|i| {
            let (t, b) = (wide(mesh.tangents()[i]), wide(mesh.bitangents()[i]));
            [
                d.dot(t) + SECONDARY_WEIGHT * secondary.dot(t),
                d.dot(b) + SECONDARY_WEIGHT * secondary.dot(b),
            ]
        })
        .collect()
}

/// Barycentric vertex areas and the area of each connected component (f64, face order).
fn vertex_areas(mesh: &FurMesh, components: &[u32]) -> (Vec<f64>, Vec<f64>) {
    let positions = mesh.positions();
    let count = mesh.topology().components();
    let mut area = vec![0.0; mesh.vertex_count()];
    let mut component_area = vec![0.0; count];
    for (f, tri) in mesh.triangles().iter().enumerate() {
        if mesh.degenerate_faces()[f] {
            continue;
        }
        let p = tri.map(|v| wide(positions[v as usize]));
        let a = 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).length();
        for &v in tri {
            area[v as usize] += a / 3.0;
        }
        let c = components[tri[0] as usize];
        if c != NO_COMPONENT {
            component_area[c as usize] += a;
        }
    }
    (area, component_area)
}

#[cfg(test)]
mod tests;
