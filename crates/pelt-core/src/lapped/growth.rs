//! Patch growth (Praun et al. 2000, §4.1, in the non-overlapping form of Lengyel et al. 2001,
//! §2.1): seeds are taken from the furred units in a seeded random order, and a patch grows from
//! its seed by whole units (polygons) across edges until its distortion would exceed the limits.
//! Every furred unit ends in exactly one patch: a seed is accepted whatever its own distortion
//! (laid out rigidly, so it is never flipped).
//!
//! Growth alternates two steps. The fast local step adds candidates one by one, breadth-first:
//! a unit's new vertices are unfolded from the patch and relaxed against it, and the unit joins
//! if its faces keep the patch within the limits. Local steps drift (each face fits itself), so
//! from 512 faces on, whenever the patch has doubled, it is solved as a whole (the least-squares
//! fit of [`super::parameterization`]) and judged again; units added since the last such
//! checkpoint whose faces now break the limits are peeled off and blocked for this patch, and if
//! peeling does not help the patch returns to its last checkpoint and stops. Blocked units wait
//! for a later patch. Smaller patches keep their local layout, which was judged face by face on
//! the very UVs it outputs; so does a last small addition after the final checkpoint.
//!
//! A patch stays a topological disk: a unit that would close a loop (around a handle, a band of
//! a sphere, or a hole) could only join with a parameterization torn along the loop. Candidates
//! are put back in the queue with a fixed probability when they come up, which makes the order,
//! and so the boundary where the limits stop a patch, irregular: seams of neighbouring patches
//! do not line up.
//!
//! Growth is sequential (each patch depends on the ones before); the parallel work is the u/v
//! solve pair of each checkpoint and everything before and after growth.

use std::collections::VecDeque;

use super::faces::{Face, NO_UNIT, Units, neighbours};
use super::parameterization::{Element, System, UNIT_SWEEPS, stiffness};
use super::quality::{FaceMetrics, metrics};
use crate::error::Result;
use crate::mesh::{FurMesh, NO_EDGE};
use crate::progress::Progress;
use crate::rng::Rng;

/// Marks a unit in no patch, and an unplaced vertex.
pub(super) const NONE: u32 = u32::MAX;
/// Probability that a candidate is tried when it comes up rather than put back.
const JOIN_PROBABILITY: f64 = 0.7;
/// Most times a candidate is put back at random, and most retries of one that would close a
/// loop (it may fit once its neighbours have joined).
const MAX_DEFERRALS: u8 = 2;
const MAX_LOOP_RETRIES: u8 = 4;
/// Faces at the first checkpoint; later ones come when the patch has doubled.
const FIRST_CHECKPOINT: usize = 512;
/// Growth since the last checkpoint below 1/LAST_SHARE of the patch ends it without another.
const LAST_SHARE: usize = 8;
/// Peeling rounds at a checkpoint before the patch falls back to the previous one.
const PEEL_ROUNDS: usize = 3;
/// A face whose alignment error (times its confidence) exceeds this many times the mean limit
/// marks its unit for peeling.
const FACE_ALIGNMENT_FACTOR: f64 = 4.0;
/// Random streams under the user's seed.
const STREAM_ORDER: u64 = 1;
const STREAM_GROWTH: u64 = 2;

/// When a patch has grown too far (all figures over faces of nonzero area).
#[derive(Debug, Clone, Copy)]
pub(super) struct Limits {
    /// Largest area-weighted mean of alignment error times confidence, radians.
    pub mean_alignment: f64,
    /// Largest alignment error times confidence of any face, radians.
    pub face_alignment: f64,
    /// Faces count as stretched outside `[1/stretch, stretch]`.
    pub stretch: f64,
    /// Largest share of the patch area that may be stretched.
    pub stretched_share: f64,
    /// No face's singular values may leave `[1/max_stretch, max_stretch]`.
    pub max_stretch: f64,
    /// Most faces in one patch.
    pub max_faces: usize,
}

/// Area, area × alignment error × confidence, and stretched area of a set of faces.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) struct Sums {
    pub area: f64,
    pub misaligned: f64,
    pub stretched: f64,
}

impl Sums {
    pub(super) fn add(self, other: Sums) -> Sums {
        Sums {
            area: self.area + other.area,
            misaligned: self.misaligned + other.misaligned,
            stretched: self.stretched + other.stretched,
        }
    }
}

impl Limits {
    /// The contribution of a face with Jacobian metrics `m`, or `None` if the face breaks a
    /// hard limit (flipped or collapsed, a singular value outside `[1/max, max]`, or misaligned
    /// beyond the face limit).
    pub(super) fn face(&self, face: &Face, m: &FaceMetrics) -> Option<Sums> {
        if m.flipped() || m.sigma[0] > self.max_stretch || m.sigma[1] * self.max_stretch < 1.0 {
            return None;
        }
        if m.alignment * face.confidence > self.face_alignment {
            return None;
        }
        let stretched = m.sigma[0] > self.stretch || m.sigma[1] * self.stretch < 1.0;
        Some(Sums {
            area: face.area,
            misaligned: face.area * m.alignment * face.confidence,
            stretched: if stretched { face.area } else { 0.0 },
        })
    }

    /// Whether a patch with these sums is within the mean limits.
    pub(super) fn within(&self, s: &Sums) -> bool {
        s.area <= 0.0
            || (s.misaligned <= self.mean_alignment * s.area && s.stretched <= self.stretched_share * s.area)
    }
}

/// Patches of every furred face: world-unit UVs per corner.
pub(super) struct Grown {
    pub patch: Vec<u32>,
    pub uv: Vec<[[f64; 2]; 3]>,
    /// Per patch: the UV of its seed's first vertex.
    pub origin: Vec<[f64; 2]>,
}

impl Grown {
    /// Renumbers the patches that still have faces `0..n`, keeping their order.
    pub(super) fn compact(&mut self) {
        let mut new_id = vec![NONE; self.origin.len()];
        for &p in &self.patch {
            if p != NONE {
                new_id[p as usize] = 0;
            }
        }
        let mut origin = Vec::new();
        for (p, id) in new_id.iter_mut().enumerate() {
            if *id == 0 {
                *id = origin.len() as u32;
                origin.push(self.origin[p]);
            }
        }
        for p in &mut self.patch {
            if *p != NONE {
                *p = new_id[*p as usize];
            }
        }
        self.origin = origin;
    }
}

struct Grower<'a> {
    mesh: &'a FurMesh,
    faces: &'a [Face],
    units: &'a Units,
    limits: Limits,
    /// Patch of each unit, or NONE.
    unit_patch: Vec<u32>,
    /// Per unit: patch id + 1 of the patch that blocked it.
    blocked: Vec<u32>,
    /// Per unit: the stamp of the last queue it entered (or connectivity search that saw it).
    seen: Vec<u64>,
    stamp: u64,
    /// Per vertex: its local index in the patch being grown, or NONE.
    local: Vec<u32>,
    /// Per edge: faces of the patch being grown that use it.
    edge_uses: Vec<u32>,
    /// Per vertex: a UV kept while the patch is rebuilt, valid where `stash_stamp` is current.
    stash: Vec<[f64; 2]>,
    stash_stamp: Vec<u64>,
    // The patch being grown.
    patch_units: Vec<u32>,
    patch_faces: Vec<u32>,
    patch_vertices: Vec<u32>,
    sums: Sums,
    system: System,
    scratch: Vec<u32>,
}

/// Grows patches over all units of `units`.
pub(super) fn grow(
    mesh: &FurMesh,
    faces: &[Face],
    units: &Units,
    limits: Limits,
    seed: u64,
    progress: &Progress<'_>,
) -> Result<Grown> {
    let mut order: Vec<u32> = (0..units.len() as u32).collect();
    let mut rng = Rng::stream(seed, STREAM_ORDER, 0);
    for i in (1..order.len()).rev() {
        order.swap(i, rng.below(i as u64 + 1) as usize);
    }
    let mut grower = Grower {
        mesh,
        faces,
        units,
        limits,
        unit_patch: vec![NONE; units.len()],
        blocked: vec![0; units.len()],
        seen: vec![0; units.len()],
        stamp: 0,
        local: vec![NONE; mesh.vertex_count()],
        edge_uses: vec![0; mesh.topology().edges().len()],
        stash: vec![[0.0; 2]; mesh.vertex_count()],
        stash_stamp: vec![0; mesh.vertex_count()],
        patch_units: Vec::new(),
        patch_faces: Vec::new(),
        patch_vertices: Vec::new(),
        sums: Sums::default(),
        system: System::default(),
        scratch: Vec::new(),
    };
    let mut patch = vec![NONE; mesh.face_count()];
    let mut uv = vec![[[0.0; 2]; 3]; mesh.face_count()];
    let mut origin = Vec::new();
    let mut count = 0u32;
    for &seed_unit in &order {
        if grower.unit_patch[seed_unit as usize] != NONE {
            continue;
        }
        let mut rng = Rng::stream(seed, STREAM_GROWTH, u64::from(count));
        grower.grow_one(seed_unit, count, &mut rng);
        for &f in &grower.patch_faces {
            let tri = mesh.triangles()[f as usize];
            patch[f as usize] = count;
            uv[f as usize] = tri.map(|v| {
                let l = grower.local[v as usize] as usize;
                [grower.system.uv[0][l], grower.system.uv[1][l]]
            });
        }
        origin.push([grower.system.uv[0][0], grower.system.uv[1][0]]);
        progress.advance(grower.patch_faces.len())?;
        grower.release();
        count += 1;
    }
    Ok(Grown { patch, uv, origin })
}

impl<'a> Grower<'a> {
    fn grow_one(&mut self, seed_unit: u32, id: u32, rng: &mut Rng) {
        self.try_unit(seed_unit, id, true);
        let mut committed = 1;
        let mut saved = self.current_uv();
        let mut checkpoint = FIRST_CHECKPOINT;
        loop {
            let mut queue = self.queue(id);
            let before = self.patch_faces.len();
            let limit = checkpoint.min(self.limits.max_faces);
            self.local_steps(&mut queue, id, rng, limit);
            if self.patch_units.len() == committed {
                break;
            }
            // A last small addition stays as the local steps placed it: their faces were judged
            // on those very UVs, and a whole solve for a few units would cost more than the
            // rest of the patch.
            if self.patch_faces.len() < limit && (self.patch_faces.len() - before) * LAST_SHARE < before {
                break;
            }
            if self.checkpoint(committed, id) {
                committed = self.patch_units.len();
                saved = self.current_uv();
            } else {
                let kept = self.patch_units[..committed].to_vec();
                self.rebuild(&kept, &saved, id);
                break;
            }
            if self.patch_faces.len() >= self.limits.max_faces {
                break;
            }
            checkpoint = 2 * self.patch_faces.len();
        }
    }

    /// Forgets the finished patch's per-vertex and per-edge state.
    fn release(&mut self) {
        for &v in &self.patch_vertices {
            self.local[v as usize] = NONE;
        }
        for &f in &self.patch_faces {
            for e in self.mesh.topology().face_edges()[f as usize] {
                if e != NO_EDGE {
                    self.edge_uses[e as usize] = 0;
                }
            }
        }
        self.patch_units.clear();
        self.patch_faces.clear();
        self.patch_vertices.clear();
        self.system.clear();
        self.sums = Sums::default();
    }

    /// (vertex, UV) of every vertex of the patch.
    fn current_uv(&self) -> Vec<(u32, [f64; 2])> {
        self.patch_vertices
            .iter()
            .map(|&v| {
                let l = self.local[v as usize] as usize;
                (v, [self.system.uv[0][l], self.system.uv[1][l]])
            })
            .collect()
    }

    /// Whether unit `w` may join patch `id`.
    fn free(&self, w: u32, id: u32) -> bool {
        w != NO_UNIT && self.unit_patch[w as usize] == NONE && self.blocked[w as usize] != id + 1
    }

    /// Units across the edges of unit `u` (possibly repeated).
    fn adjacent_units(&mut self, u: u32, out: &mut Vec<u32>) {
        out.clear();
        let mut across = std::mem::take(&mut self.scratch);
        for &f in self.units.faces(u) {
            neighbours(self.mesh, f, &mut across);
            out.extend(
                across
                    .iter()
                    .map(|&g| self.units.of_face[g as usize])
                    .filter(|&w| w != u),
            );
        }
        self.scratch = across;
    }

    /// A fresh queue of the free units next to the patch.
    fn queue(&mut self, id: u32) -> VecDeque<(u32, u8)> {
        self.stamp += 1;
        let mut queue = VecDeque::new();
        let mut found = Vec::new();
        for i in 0..self.patch_units.len() {
            self.adjacent_units(self.patch_units[i], &mut found);
            for &w in &found {
                if self.free(w, id) && self.seen[w as usize] != self.stamp {
                    self.seen[w as usize] = self.stamp;
                    queue.push_back((w, 0));
                }
            }
        }
        queue
    }

    /// Local steps over the queue until it is empty or the patch has `limit` faces.
    fn local_steps(&mut self, queue: &mut VecDeque<(u32, u8)>, id: u32, rng: &mut Rng, limit: usize) {
        let mut found = Vec::new();
        while self.patch_faces.len() < limit {
            let Some((u, tries)) = queue.pop_front() else {
                break;
            };
            if !self.free(u, id) {
                continue;
            }
            if tries < MAX_DEFERRALS && !queue.is_empty() && rng.next_f64() >= JOIN_PROBABILITY {
                queue.push_back((u, tries + 1));
                continue;
            }
            if !self.keeps_disk(u) {
                if tries < MAX_DEFERRALS + MAX_LOOP_RETRIES {
                    queue.push_back((u, tries.max(MAX_DEFERRALS) + 1));
                }
                continue;
            }
            if self.try_unit(u, id, false) {
                self.adjacent_units(u, &mut found);
                for &w in &found {
                    if self.free(w, id) && self.seen[w as usize] != self.stamp {
                        self.seen[w as usize] = self.stamp;
                        queue.push_back((w, 0));
                    }
                }
            } else {
                self.blocked[u as usize] = id + 1;
            }
        }
    }

    /// Whether adding unit `u` keeps the patch a topological disk: its Euler characteristic
    /// `V - E + F` must not change. Units with a zero-area face are let through (they carry no
    /// weight in the fit).
    fn keeps_disk(&self, u: u32) -> bool {
        let faces = self.units.faces(u);
        if faces.iter().any(|&f| self.mesh.degenerate_faces()[f as usize]) {
            return true;
        }
        let (mut vertices, mut edges) = (Vec::new(), Vec::new());
        for &f in faces {
            vertices.extend(self.mesh.triangles()[f as usize]);
            edges.extend(self.mesh.topology().face_edges()[f as usize]);
        }
        vertices.sort_unstable();
        vertices.dedup();
        edges.sort_unstable();
        edges.dedup();
        let new_vertices = vertices
            .iter()
            .filter(|&&v| self.local[v as usize] == NONE)
            .count();
        let new_edges = edges
            .iter()
            .filter(|&&e| e != NO_EDGE && self.edge_uses[e as usize] == 0)
            .count();
        new_vertices + faces.len() == new_edges
    }

    /// The local step: places unit `u`, relaxes its new vertices against the patch, and keeps
    /// it if its faces keep the patch within the limits (or `force`).
    fn try_unit(&mut self, u: u32, id: u32, force: bool) -> bool {
        let first_new = self.system.vertex_count();
        let vertices_before = self.patch_vertices.len();
        self.place(u, None);
        let elements = self.elements(u);
        // A seed keeps its unfolded (isometric, unflipped) layout: with nothing around it to
        // hold it, a fit to targets that turn sharply inside it (near a singularity) could fold.
        if !force {
            self.system.relax(first_new as u32, &elements, UNIT_SWEEPS);
        }
        let mut unit = Sums::default();
        let mut fits = true;
        for (local, face, _) in &elements {
            if face.area > 0.0 {
                match self
                    .limits
                    .face(face, &metrics(self.system.gradients(*local, face)))
                {
                    Some(s) => unit = unit.add(s),
                    None => fits = false,
                }
            }
        }
        if force || (fits && self.limits.within(&self.sums.add(unit))) {
            self.commit(u, id, elements);
            self.sums = self.sums.add(unit);
            return true;
        }
        for &v in &self.patch_vertices[vertices_before..] {
            self.local[v as usize] = NONE;
        }
        self.patch_vertices.truncate(vertices_before);
        self.system.truncate_vertices(first_new);
        false
    }

    /// Local corners, face and stiffness of each face of unit `u` (all corners placed).
    fn elements(&self, u: u32) -> Vec<Element<'a>> {
        let faces: &'a [Face] = self.faces;
        self.units
            .faces(u)
            .iter()
            .map(|&f| {
                let tri = self.mesh.triangles()[f as usize];
                let face = &faces[f as usize];
                (tri.map(|v| self.local[v as usize]), face, stiffness(face))
            })
            .collect()
    }

    /// Adds unit `u`'s faces to the patch.
    fn commit(&mut self, u: u32, id: u32, elements: Vec<Element<'a>>) {
        for (local, face, k) in elements {
            self.system.add_face(local, face, k);
        }
        for &f in self.units.faces(u) {
            for e in self.mesh.topology().face_edges()[f as usize] {
                if e != NO_EDGE {
                    self.edge_uses[e as usize] += 1;
                }
            }
        }
        self.patch_faces.extend_from_slice(self.units.faces(u));
        self.patch_units.push(u);
        self.unit_patch[u as usize] = id;
    }

    /// Solves the patch as a whole and judges it; units after the first `committed` whose faces
    /// break the limits are peeled off (with any that lose their connection) and blocked.
    /// Returns whether the patch ends within the limits.
    fn checkpoint(&mut self, committed: usize, id: u32) -> bool {
        for _ in 0..PEEL_ROUNDS {
            self.system.solve();
            if let Some(sums) = self.judge() {
                self.sums = sums;
                return true;
            }
            let bad: Vec<u32> = self.patch_units[committed..]
                .iter()
                .copied()
                .filter(|&u| self.out_of_bounds(u))
                .collect();
            if bad.is_empty() {
                return false;
            }
            for &u in &bad {
                self.blocked[u as usize] = id + 1;
            }
            let kept = self.connected(committed, id);
            let current = self.current_uv();
            self.rebuild(&kept, &current, id);
        }
        false
    }

    /// The units of the patch that are not blocked and connect to the first `committed` units
    /// through unblocked units, in their order.
    fn connected(&mut self, committed: usize, id: u32) -> Vec<u32> {
        self.stamp += 1;
        let stamp = self.stamp;
        let mut stack: Vec<u32> = self.patch_units[..committed].to_vec();
        for &u in &stack {
            self.seen[u as usize] = stamp;
        }
        let mut found = Vec::new();
        while let Some(u) = stack.pop() {
            self.adjacent_units(u, &mut found);
            for &w in &found {
                if w != NO_UNIT
                    && self.unit_patch[w as usize] == id
                    && self.blocked[w as usize] != id + 1
                    && self.seen[w as usize] != stamp
                {
                    self.seen[w as usize] = stamp;
                    stack.push(w);
                }
            }
        }
        self.patch_units
            .iter()
            .copied()
            .filter(|&u| self.seen[u as usize] == stamp)
            .collect()
    }

    /// Rebuilds the patch from `units` (in order), starting each vertex at its UV in `uv` when
    /// it has one there.
    fn rebuild(&mut self, units: &[u32], uv: &[(u32, [f64; 2])], id: u32) {
        for &u in &self.patch_units {
            self.unit_patch[u as usize] = NONE;
        }
        self.release();
        self.stamp += 1;
        let stamp = self.stamp;
        for &(v, x) in uv {
            self.stash[v as usize] = x;
            self.stash_stamp[v as usize] = stamp;
        }
        for &u in units {
            self.place(u, Some(stamp));
            let elements = self.elements(u);
            self.commit(u, id, elements);
        }
    }

    /// The sums of the whole patch under its current parameterization, or `None` if it breaks
    /// a limit.
    fn judge(&self) -> Option<Sums> {
        let mut sums = Sums::default();
        for &f in &self.patch_faces {
            let face = &self.faces[f as usize];
            if face.area > 0.0 {
                let tri = self.mesh.triangles()[f as usize];
                let m = metrics(self.system.gradients(tri.map(|v| self.local[v as usize]), face));
                sums = sums.add(self.limits.face(face, &m)?);
            }
        }
        self.limits.within(&sums).then_some(sums)
    }

    /// Whether a face of unit `u` breaks a hard limit, is stretched, or is misaligned by more
    /// than [`FACE_ALIGNMENT_FACTOR`] times the mean limit.
    fn out_of_bounds(&self, u: u32) -> bool {
        let limits = &self.limits;
        self.units.faces(u).iter().any(|&f| {
            let face = &self.faces[f as usize];
            if face.area <= 0.0 {
                return false;
            }
            let tri = self.mesh.triangles()[f as usize];
            let m = metrics(self.system.gradients(tri.map(|v| self.local[v as usize]), face));
            m.flipped()
                || m.sigma[0] > limits.stretch
                || m.sigma[1] * limits.stretch < 1.0
                || m.alignment * face.confidence > FACE_ALIGNMENT_FACTOR * limits.mean_alignment
        })
    }

    /// Gives unit `u`'s unplaced vertices a start: their stashed UV (when `stash` is the current
    /// stash stamp and they have one), else unfolded from a placed corner along the face's
    /// target map (faces reached through placed corners first; a face of a polygon in pieces
    /// with no placed corner starts its distance away along u, its offset within the patch
    /// being free).
    fn place(&mut self, u: u32, stash: Option<u64>) {
        let unit_faces = self.units.faces(u);
        if let Some(stamp) = stash {
            for &f in unit_faces {
                for v in self.mesh.triangles()[f as usize] {
                    if self.local[v as usize] == NONE && self.stash_stamp[v as usize] == stamp {
                        self.local[v as usize] = self.system.add_vertex(self.stash[v as usize]);
                        self.patch_vertices.push(v);
                    }
                }
            }
        }
        let mut done = vec![false; unit_faces.len()];
        while done.contains(&false) {
            let mut progressed = false;
            for (i, &f) in unit_faces.iter().enumerate() {
                let tri = self.mesh.triangles()[f as usize];
                if done[i] || tri.iter().all(|&v| self.local[v as usize] == NONE) {
                    continue;
                }
                self.unfold(f, false);
                done[i] = true;
                progressed = true;
            }
            if !progressed {
                let i = done.iter().position(|d| !d).unwrap_or(0);
                self.unfold(unit_faces[i], true);
                done[i] = true;
            }
        }
    }

    /// Places the unplaced corners of face `f`: across an edge with both ends placed, by
    /// unfolding the face rigidly about that edge (isometric and never flipped); from a single
    /// placed corner, along the face's target map; or (`detached`) from the patch's first vertex.
    fn unfold(&mut self, f: u32, detached: bool) {
        let tri = self.mesh.triangles()[f as usize];
        let face = &self.faces[f as usize];
        let placed: Vec<usize> = (0..3).filter(|&c| self.local[tri[c] as usize] != NONE).collect();
        let at = |s: &Self, c: usize| {
            let l = s.local[tri[c] as usize] as usize;
            [s.system.uv[0][l], s.system.uv[1][l]]
        };
        // Rotation (cos, sin) taking the face's frame onto the patch's layout, and an anchor.
        let (rotation, origin, start) = match placed.as_slice() {
            _ if detached && !self.patch_vertices.is_empty() => {
                let p0 = self.mesh.positions()[self.patch_vertices[0] as usize];
                let p = self.mesh.positions()[tri[0] as usize];
                let d = [0, 1, 2].map(|k| f64::from(p[k]) - f64::from(p0[k]));
                let away = d[0].hypot(d[1]).hypot(d[2]);
                (
                    [1.0, 0.0],
                    face.corners[0],
                    [self.system.uv[0][0] + away, self.system.uv[1][0]],
                )
            }
            [] => ([1.0, 0.0], face.corners[0], [0.0, 0.0]),
            &[a, b] => {
                let (ua, ub) = (at(self, a), at(self, b));
                let (xa, xb) = (face.corners[a], face.corners[b]);
                let (du, dx) = ([ub[0] - ua[0], ub[1] - ua[1]], [xb[0] - xa[0], xb[1] - xa[1]]);
                let angle = du[1].atan2(du[0]) - dx[1].atan2(dx[0]);
                let usable = du[0].hypot(du[1]) > 0.0 && dx[0].hypot(dx[1]) > 0.0;
                let rotation = if usable {
                    [angle.cos(), angle.sin()]
                } else {
                    [1.0, 0.0]
                };
                (rotation, xa, ua)
            }
            _ => ([1.0, 0.0], face.corners[placed[0]], at(self, placed[0])),
        };
        for (&v, corner) in tri.iter().zip(face.corners) {
            let v = v as usize;
            if self.local[v] == NONE {
                let d = [corner[0] - origin[0], corner[1] - origin[1]];
                let uv = [
                    start[0] + rotation[0] * d[0] - rotation[1] * d[1],
                    start[1] + rotation[1] * d[0] + rotation[0] * d[1],
                ];
                self.local[v] = self.system.add_vertex(uv);
                self.patch_vertices.push(v as u32);
            }
        }
    }
}
