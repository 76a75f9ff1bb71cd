//! Stage keys: a hash of exactly the inputs a stage reads (DESIGN.md §1), so a re-bake can tell
//! which stages are unchanged. The keys live in memory only (one process), so `DefaultHasher`'s
//! fixed-key SipHash is enough; parameters hash through their `Debug` form, which prints every
//! field and floats in their shortest round-trip spelling.

use std::hash::{DefaultHasher, Hasher};

use crate::FurMesh;

/// Accumulates one stage key.
pub(super) struct KeyHasher(DefaultHasher);

impl KeyHasher {
    /// A key for the stage `stage` (so equal inputs of different stages never collide).
    pub(super) fn new(stage: &str) -> Self {
        let mut hasher = DefaultHasher::new();
        hasher.write(stage.as_bytes());
        KeyHasher(hasher)
    }

    /// Adds a parameter struct by its `Debug` form.
    pub(super) fn params(mut self, params: &impl std::fmt::Debug) -> Self {
        self.0.write(format!("{params:?}").as_bytes());
        self
    }

    /// Adds a key computed earlier (a stage this one reads from).
    pub(super) fn key(mut self, key: u64) -> Self {
        self.0.write_u64(key);
        self
    }

    /// Adds a float array (bit patterns; the mesh is validated, so there is no NaN to alias).
    pub(super) fn floats<const C: usize>(mut self, rows: Option<&[[f32; C]]>) -> Self {
        match rows {
            None => self.0.write_u8(0),
            Some(rows) => {
                self.0.write_u8(1);
                self.0.write_usize(rows.len());
                for row in rows {
                    for value in row {
                        self.0.write_u32(value.to_bits());
                    }
                }
            }
        }
        self
    }

    /// Adds an integer array.
    pub(super) fn ints(mut self, values: impl Iterator<Item = u32>) -> Self {
        let mut count = 0usize;
        for value in values {
            self.0.write_u32(value);
            count += 1;
        }
        self.0.write_usize(count);
        self
    }

    pub(super) fn finish(self) -> u64 {
        self.0.finish()
    }
}

/// What the lapped patches read of a mesh: geometry, given normals, comb, polygons, and which
/// vertices are bald (the lengths themselves only scale the fur at render time).
pub(super) fn patch_mesh_key(hasher: KeyHasher, mesh: &FurMesh) -> KeyHasher {
    let normals = mesh.normals_given().then(|| mesh.normals());
    // The bald vertices' indices: no lengths and lengths that are all nonzero give the same key.
    let bald = mesh.length().unwrap_or_default().iter().enumerate();
    hasher
        .floats(Some(mesh.positions()))
        .ints(mesh.triangles().iter().flatten().copied())
        .floats(normals)
        .floats(mesh.comb())
        .ints(mesh.polygons().unwrap_or_default().iter().copied())
        .ints(bald.filter(|&(_, &l)| l == 0.0).map(|(v, _)| v as u32))
}
