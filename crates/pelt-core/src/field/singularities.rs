//! Singularities of a vertex-based direction field: the index of each face (Knöppel et al. 2013,
//! §5.3). Around a face's three sides the field turns by `δ` relative to the transport; together
//! with the face's holonomy `Ω` (its angle defect) the turn is a whole number of revolutions,
//! the index: 0 for a regular face, ±1 for a source, sink, vortex or saddle. By Poincaré–Hopf the
//! indices of a closed component sum to its Euler characteristic.

use std::f64::consts::{PI, TAU};

use rayon::prelude::*;

use super::connection::{conj, mul};
use crate::mesh::{FurMesh, NO_EDGE};

/// A face around which the field turns.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct Singularity {
    /// Triangle index.
    pub face: u32,
    /// Turns of the field around the face's boundary (counter-clockwise about its normal).
    pub index: i32,
}

/// Angle of a complex number in `(-π, π]`.
fn arg(z: [f64; 2]) -> f64 {
    z[1].atan2(z[0])
}

/// Wraps an angle into `(-π, π]`.
fn wrap(a: f64) -> f64 {
    let w = a - TAU * (a / TAU).round();
    if w <= -PI { w + TAU } else { w }
}

/// Faces with a nonzero index. `unit` holds the unit field per vertex (its frame's complex
/// angle); `transport[e]` carries edge `e`'s lower vertex's frame to the higher one's.
pub(super) fn find(mesh: &FurMesh, unit: &[[f64; 2]], transport: &[[f64; 2]]) -> Vec<Singularity> {
    let topology = mesh.topology();
    let degenerate = mesh.degenerate_faces();
    (0..mesh.face_count())
        .into_par_iter()
        .filter_map(|f| {
            let sides = topology.face_edges()[f];
            if degenerate[f] || sides.contains(&NO_EDGE) {
                return None;
            }
            let tri = mesh.triangles()[f];
            let (mut turn, mut holonomy) = (0.0, 0.0);
            for c in 0..3 {
                let (a, b) = (tri[c], tri[(c + 1) % 3]);
                let r = transport[sides[c] as usize];
                let r = if a < b { r } else { conj(r) };
                // Field turn along a→b, measured against the transported field of a.
                turn += arg(mul(unit[b as usize], conj(mul(r, unit[a as usize]))));
                holonomy += arg(r);
            }
            let index = ((turn + wrap(holonomy)) / TAU).round() as i32;
            (index != 0).then_some(Singularity {
                face: f as u32,
                index,
            })
        })
        .collect()
}
