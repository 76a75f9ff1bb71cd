//! The local parameterization of one patch, after the least-squares fit of Praun et al. 2000
//! (§4.2) in linear form. Each face wants its Jacobian to be the identity in its field-aligned
//! frame (u along the field, unit scale); the patch minimizes
//!
//! ```text
//! Σ_f A_f ( |∇u - e_u|²  +  λ (∇v·e_u)²  +  (∇v·e_v - 1)² )
//! ```
//!
//! one Poisson problem with Neumann boundary per coordinate (cotangent stiffness for u, an
//! anisotropic one for v). The texture's u axis lies along the level lines of v, so the
//! alignment error is the angle of `∇v` from `e_v`: the weight `λ` on the along-field part of
//! `∇v` makes the fit trade stretch (tolerated to ±25%) for alignment (wanted within degrees).
//!
//! While a patch grows, each new unit's vertices are placed by unfolding from the patch and
//! relaxed by Gauss–Seidel sweeps against the fixed patch (the fast local step, [`System::relax`]);
//! at the grower's checkpoints conjugate gradients solve the whole system from that start
//! ([`System::solve`], u and v on two workers).
//!
//! Units are world units at this stage (the target scale is 1); dividing by the tile size later
//! gives tile units, so the whole construction is scale-invariant.

use super::faces::Face;
use crate::cg;

/// Relative residual at which a solve stops: the distortion figures it feeds are compared with
/// tolerances of percents and degrees, which a tighter solve does not change.
const TOLERANCE: f64 = 1e-3;
/// Iteration cap per solve; a capped solve is a valid, only less optimal, parameterization.
const MAX_ITERATIONS: usize = 2000;
/// Below this many vertices u and v are solved one after the other.
const JOIN_VERTICES: usize = 256;
/// Gauss–Seidel sweeps over a new unit's vertices (a unit has few, mostly one).
pub(super) const UNIT_SWEEPS: usize = 4;

/// `λ` above. Larger values follow the field more closely but stretch more and slow the solve
/// (the anisotropy conditions the system worse); 4 keeps the mean alignment error near 1° on
/// the test meshes.
const ALIGNMENT_WEIGHT: f64 = 4.0;

/// Stiffness of u and of v on `face` (entries 00, 11, 22, 01, 12, 20). The alignment weight
/// fades with the face's confidence: near a singularity the fit keeps scale rather than follow a
/// direction that turns too fast to follow.
pub(super) fn stiffness(face: &Face) -> [[f64; 6]; 2] {
    let weight = 1.0 + (ALIGNMENT_WEIGHT - 1.0) * face.confidence;
    [face.stiffness([1.0, 1.0]), face.stiffness([weight, 1.0])]
}

/// A face in a patch: its local corner indices, the face, and the stiffness of u and of v.
pub(super) type Element<'a> = ([u32; 3], &'a Face, [[f64; 6]; 2]);

/// Entry `(c, d)` of a symmetric 3×3 stored as 00, 11, 22, 01, 12, 20.
fn entry(k: &[f64; 6], c: usize, d: usize) -> f64 {
    if c == d {
        k[c]
    } else {
        match c + d {
            1 => k[3],
            3 => k[4],
            _ => k[5],
        }
    }
}

/// The linear system of one patch.
#[derive(Default)]
pub(super) struct System {
    /// Per patch face: local corner indices and the stiffness of u and of v.
    elements: Vec<([u32; 3], [[f64; 6]; 2])>,
    diagonal: [Vec<f64>; 2],
    load: [Vec<f64>; 2],
    /// Current (u, v) per local vertex, world units.
    pub uv: [Vec<f64>; 2],
}

impl System {
    pub(super) fn clear(&mut self) {
        self.elements.clear();
        self.diagonal.iter_mut().for_each(Vec::clear);
        self.load.iter_mut().for_each(Vec::clear);
        self.uv.iter_mut().for_each(Vec::clear);
    }

    /// Number of local vertices.
    pub(super) fn vertex_count(&self) -> usize {
        self.uv[0].len()
    }

    /// Adds a vertex with start value `uv`; returns its local index.
    pub(super) fn add_vertex(&mut self, uv: [f64; 2]) -> u32 {
        for (k, value) in uv.into_iter().enumerate() {
            self.diagonal[k].push(0.0);
            self.load[k].push(0.0);
            self.uv[k].push(value);
        }
        (self.uv[0].len() - 1) as u32
    }

    /// Drops the vertices from `count` on (no added face may use them).
    pub(super) fn truncate_vertices(&mut self, count: usize) {
        for k in 0..2 {
            self.diagonal[k].truncate(count);
            self.load[k].truncate(count);
            self.uv[k].truncate(count);
        }
    }

    /// Adds face `face` with corners at the local vertices `local` to the system.
    pub(super) fn add_face(&mut self, local: [u32; 3], face: &Face, k: [[f64; 6]; 2]) {
        for (c, &v) in local.iter().enumerate() {
            for (coordinate, stiffness) in k.iter().enumerate() {
                self.diagonal[coordinate][v as usize] += stiffness[c];
                // Target gradient e_u (e_v): load A ∇φ_i·e_u (A ∇φ_i·e_v).
                self.load[coordinate][v as usize] += face.grad_area[c][coordinate];
            }
        }
        self.elements.push((local, k));
    }

    /// Gauss–Seidel sweeps over the vertices from `first` on, minimizing the energy of `faces`
    /// (local corners, face, stiffness) with every older vertex held fixed.
    pub(super) fn relax(&mut self, first: u32, faces: &[Element<'_>], sweeps: usize) {
        // (free vertex, face, corner) sorted by vertex: each sweep visits a vertex's faces only.
        let mut incidence: Vec<(u32, usize, usize)> = faces
            .iter()
            .enumerate()
            .flat_map(|(f, (local, _, _))| (0..3).map(move |c| (local[c], f, c)))
            .filter(|&(v, _, _)| v >= first)
            .collect();
        incidence.sort_unstable();
        for _ in 0..sweeps {
            let mut i = 0;
            while i < incidence.len() {
                let p = incidence[i].0;
                let run = incidence[i..].iter().take_while(|e| e.0 == p).count();
                for coordinate in 0..2 {
                    let x = &self.uv[coordinate];
                    let (mut diagonal, mut rhs) = (0.0, 0.0);
                    for &(_, f, c) in &incidence[i..i + run] {
                        let (local, face, k) = &faces[f];
                        let k = &k[coordinate];
                        diagonal += entry(k, c, c);
                        rhs += face.grad_area[c][coordinate];
                        for d in (0..3).filter(|&d| d != c) {
                            rhs -= entry(k, c, d) * x[local[d] as usize];
                        }
                    }
                    if diagonal > 0.0 {
                        self.uv[coordinate][p as usize] = rhs / diagonal;
                    }
                }
                i += run;
            }
        }
    }

    /// The stiffness of both coordinates as compressed rows (faces summed per vertex pair):
    /// column indices, and the values of u and of v.
    fn rows(&self) -> (Vec<u32>, Vec<u32>, [Vec<f64>; 2]) {
        let n = self.vertex_count();
        let mut start = vec![0usize; n + 1];
        for (local, _) in &self.elements {
            for &v in local {
                start[v as usize + 1] += 3;
            }
        }
        for i in 0..n {
            start[i + 1] += start[i];
        }
        let mut raw = vec![(0u32, 0.0f64, 0.0f64); start[n]];
        let mut fill = start.clone();
        for (local, k) in &self.elements {
            for (c, &row) in local.iter().enumerate() {
                let row = row as usize;
                for (d, &column) in local.iter().enumerate() {
                    raw[fill[row]] = (column, entry(&k[0], c, d), entry(&k[1], c, d));
                    fill[row] += 1;
                }
            }
        }
        let mut offsets = Vec::with_capacity(n + 1);
        let mut columns = Vec::with_capacity(start[n] / 2);
        let mut values = [Vec::with_capacity(start[n] / 2), Vec::with_capacity(start[n] / 2)];
        offsets.push(0u32);
        for i in 0..n {
            let row = &mut raw[start[i]..start[i + 1]];
            row.sort_by_key(|e| e.0);
            for (j, &(col, u, v)) in row.iter().enumerate() {
                // Entries of one column are adjacent after the sort: add to the one just pushed.
                let repeated = j > 0 && row[j - 1].0 == col;
                let [values_u, values_v] = &mut values;
                match (repeated, values_u.last_mut(), values_v.last_mut()) {
                    (true, Some(last_u), Some(last_v)) => {
                        *last_u += u;
                        *last_v += v;
                    }
                    _ => {
                        columns.push(col);
                        values_u.push(u);
                        values_v.push(v);
                    }
                }
            }
            offsets.push(columns.len() as u32);
        }
        (offsets, columns, values)
    }

    /// Solves the whole system for both coordinates, starting from the current values.
    pub(super) fn solve(&mut self) {
        let (offsets, columns, values) = self.rows();
        let inv_diag = self.diagonal.each_ref().map(|d| {
            d.iter()
                .map(|&d| if d > 0.0 { 1.0 / d } else { 0.0 })
                .collect::<Vec<f64>>()
        });
        let [u, v] = &mut self.uv;
        let (load, inv_diag) = (&self.load, &inv_diag);
        let (offsets, columns) = (&offsets, &columns);
        let [values_u, values_v] = &values;
        let mut solve_u = move || {
            let apply = |x: &[f64], y: &mut [f64]| apply_rows(offsets, columns, values_u, x, y);
            cg::solve(apply, &inv_diag[0], &load[0], u, TOLERANCE, MAX_ITERATIONS)
        };
        let mut solve_v = move || {
            let apply = |x: &[f64], y: &mut [f64]| apply_rows(offsets, columns, values_v, x, y);
            cg::solve(apply, &inv_diag[1], &load[1], v, TOLERANCE, MAX_ITERATIONS)
        };
        if inv_diag[0].len() >= JOIN_VERTICES {
            rayon::join(solve_u, solve_v);
        } else {
            solve_u();
            solve_v();
        }
    }

    /// Gradients of u and v on a face with local corners `local`.
    pub(super) fn gradients(&self, local: [u32; 3], face: &Face) -> [[f64; 2]; 2] {
        [0, 1].map(|k| {
            let x = &self.uv[k];
            let mut g = [0.0; 2];
            for c in 0..3 {
                g[0] += x[local[c] as usize] * face.grad_area[c][0];
                g[1] += x[local[c] as usize] * face.grad_area[c][1];
            }
            [g[0] / face.area, g[1] / face.area]
        })
    }
}

/// `y = K x` for compressed rows.
fn apply_rows(offsets: &[u32], columns: &[u32], values: &[f64], x: &[f64], y: &mut [f64]) {
    for (i, out) in y.iter_mut().enumerate() {
        let (start, end) = (offsets[i] as usize, offsets[i + 1] as usize);
        *out = columns[start..end]
            .iter()
            .zip(&values[start..end])
            .map(|(&j, &k)| k * x[j as usize])
            .sum();
    }
}
