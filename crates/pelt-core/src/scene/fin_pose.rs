//! The fins' planes following a pose, lazily: a pose keeps its posed vertices and marks every
//! geometric level's planes out of date, and the first frame that draws a level's fins moves
//! just that level's planes ([`FinPlanes::visible_indices`] needs them). A pose followed by
//! frames at one level of detail, or with fins off, computes no plane it does not use.

use std::ops::Range;

use super::fin_cull::FinPlanes;
use crate::mesh::{fin_plane, midpoint};

pub struct PosedFinPlanes {
    planes: FinPlanes,
    /// Each fin's ends (mesh vertices).
    ends: Vec<[u32; 2]>,
    /// The last pose's vertex positions and unit normals.
    positions: Vec<[f32; 3]>,
    normals: Vec<[f32; 3]>,
    /// Fin ranges (one per geometric level) whose planes are still an earlier pose's.
    stale: Vec<Range<u32>>,
}

impl PosedFinPlanes {
    /// The rest shape's `planes` of the fins standing on `ends`.
    pub fn new(planes: FinPlanes, ends: Vec<[u32; 2]>) -> Self {
        PosedFinPlanes {
            planes,
            ends,
            positions: Vec::new(),
            normals: Vec::new(),
            stale: Vec::new(),
        }
    }

    /// Takes a pose (`positions` and unit `normals` per mesh vertex): every one of `levels`'
    /// fin ranges is out of date until a frame draws it.
    pub fn pose(
        &mut self,
        positions: &[[f32; 3]],
        normals: Vec<[f32; 3]>,
        levels: impl Iterator<Item = Range<u32>>,
    ) {
        self.positions.clear();
        self.positions.extend_from_slice(positions);
        self.normals = normals;
        self.stale = levels.collect();
    }

    /// Other fins (a scene's levels made anew): their rest `planes` and `ends`, every one of
    /// `levels`' fin ranges out of date when a pose was taken, so that the next frame brings
    /// them to it.
    pub fn replace(
        &mut self,
        planes: FinPlanes,
        ends: Vec<[u32; 2]>,
        levels: impl Iterator<Item = Range<u32>>,
    ) {
        self.planes = planes;
        self.ends = ends;
        self.stale = if self.positions.is_empty() {
            Vec::new()
        } else {
            levels.collect()
        };
    }

    /// [`FinPlanes::visible_indices`] of `fins`, their planes first brought to the last pose.
    pub fn visible_indices(&mut self, eye: [f32; 4], fins: Range<u32>) -> Vec<u32> {
        let (positions, normals) = (&self.positions, &self.normals);
        let ends = &self.ends;
        let planes = &mut self.planes;
        self.stale.retain(|range| {
            let overlaps = range.start < fins.end && fins.start < range.end;
            if overlaps {
                // A fin whose posed edge has no plane gets none: `fins.wgsl` drops it, and so
                // does this list.
                planes.update(range.clone(), ends, |[a, b]| {
                    let (a, b) = (a as usize, b as usize);
                    let plane = fin_plane([positions[a], positions[b]], [normals[a], normals[b]]);
                    (
                        midpoint(positions[a], positions[b]),
                        plane.map_or([0.0; 3], |(n, _)| n),
                    )
                });
            }
            !overlaps
        });
        self.planes.visible_indices(eye, fins)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_level_drawn_after_a_pose_is_culled_by_its_posed_planes() {
        // Two levels of one fin each, on the edge 0–1 along x with normals +z: plane normal +y.
        let positions = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]];
        let normals = vec![[0.0, 0.0, 1.0]; 2];
        let rest = FinPlanes::new(vec![[0.5, 0.0, 0.0]; 2], vec![[0.0, 1.0, 0.0]; 2]);
        let mut planes = PosedFinPlanes::new(rest, vec![[0, 1]; 2]);
        let above = [0.5, 5.0, 0.0, 1.0];
        let aside = [-5.0, 0.5, 0.0, 1.0];
        assert_eq!(planes.visible_indices(above, 0..1).len(), 6);
        assert!(planes.visible_indices(aside, 0..1).is_empty());
        // Turned a quarter about z: the edge runs along y, its plane faces −x.
        let turned = positions.map(|[x, y, z]| [-y, x, z]);
        planes.pose(&turned, normals, [0..1, 1..2].into_iter());
        assert!(planes.visible_indices(above, 0..1).is_empty());
        assert_eq!(planes.visible_indices(aside, 0..1).len(), 6);
        // The level not drawn yet waits for its frame, then follows too.
        assert_eq!((planes.stale.len(), planes.stale.first()), (1, Some(&(1..2))));
        assert_eq!(
            planes.visible_indices(aside, 1..2),
            crate::mesh::quad_triangles(1)
        );
    }

    #[test]
    fn fins_made_anew_after_a_pose_follow_it() {
        let rest = || FinPlanes::new(vec![[0.5, 0.0, 0.0]], vec![[0.0, 1.0, 0.0]]);
        let (above, aside) = ([0.5, 5.0, 0.0, 1.0], [-5.0, 0.5, 0.0, 1.0]);
        let mut unposed = PosedFinPlanes::new(rest(), vec![[0, 1]]);
        unposed.replace(rest(), vec![[0, 1]], std::iter::once(0..1));
        assert_eq!(
            unposed.visible_indices(above, 0..1).len(),
            6,
            "no pose: the rest planes"
        );
        let mut planes = PosedFinPlanes::new(rest(), vec![[0, 1]]);
        let turned = [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        planes.pose(&turned, vec![[0.0, 0.0, 1.0]; 2], std::iter::once(0..1));
        planes.replace(rest(), vec![[0, 1]], std::iter::once(0..1));
        assert!(planes.visible_indices(above, 0..1).is_empty());
        assert_eq!(planes.visible_indices(aside, 0..1).len(), 6);
    }
}
