//! The tile's strand roots bucketed in a grid, so that a triangle finds the roots its patch UVs
//! cover in every tile repeat they span without testing every strand.

use glam::Vec2;

use crate::hair::Strand;

/// The strands' roots bucketed in a grid over the unit tile, for finding those a triangle's UVs
/// cover in every tile repeat they span.
pub(super) struct RootGrid {
    side: usize,
    /// Cell `c`'s strands are `order[start[c]..start[c + 1]]`.
    start: Vec<u32>,
    order: Vec<u32>,
    roots: Vec<Vec2>,
}

impl RootGrid {
    pub(super) fn new(strands: &[Strand]) -> Self {
        let side = ((strands.len() as f64).sqrt().ceil() as usize).clamp(1, 1024);
        let roots: Vec<Vec2> = strands
            .iter()
            .map(|s| Vec2::new(s.root[0].rem_euclid(1.0) as f32, s.root[1].rem_euclid(1.0) as f32))
            .collect();
        let cell = |p: Vec2| {
            let i = ((p.x * side as f32) as usize).min(side - 1);
            let j = ((p.y * side as f32) as usize).min(side - 1);
            j * side + i
        };
        let mut start = vec![0u32; side * side + 1];
        for &p in &roots {
            start[cell(p) + 1] += 1;
        }
        for c in 0..side * side {
            start[c + 1] += start[c];
        }
        let mut fill = start.clone();
        let mut order = vec![0u32; roots.len()];
        for (k, &p) in roots.iter().enumerate() {
            let c = cell(p);
            order[fill[c] as usize] = k as u32;
            fill[c] += 1;
        }
        RootGrid {
            side,
            start,
            order,
            roots,
        }
    }

    /// Calls `f(strand, tile_x, tile_y)` for every strand whose root, moved to tile repeat
    /// `(tile_x, tile_y)`, lies inside the UV triangle `uv` (in strand order within each cell).
    pub(super) fn visit(&self, uv: &[[f32; 2]; 3], mut f: impl FnMut(usize, f32, f32)) {
        let [a, b, c] = uv.map(Vec2::from);
        let lo = a.min(b).min(c);
        let hi = a.max(b).max(c);
        let den = (b - a).perp_dot(c - a);
        if den.is_nan() || den.abs() <= 1e-12 || !(hi - lo).is_finite() || (hi - lo).max_element() > 1e4 {
            return;
        }
        let n = self.side as f32;
        for tj in lo.y.floor() as i64..=hi.y.floor() as i64 {
            for ti in lo.x.floor() as i64..=hi.x.floor() as i64 {
                let origin = Vec2::new(ti as f32, tj as f32);
                let (l, h) = ((lo - origin).max(Vec2::ZERO), (hi - origin).min(Vec2::ONE));
                if l.x > h.x || l.y > h.y {
                    continue;
                }
                let (i0, i1) = ((l.x * n) as usize, ((h.x * n) as usize).min(self.side - 1));
                let (j0, j1) = ((l.y * n) as usize, ((h.y * n) as usize).min(self.side - 1));
                for j in j0..=j1 {
                    for i in i0..=i1 {
                        let cell = j * self.side + i;
                        for &k in &self.order[self.start[cell] as usize..self.start[cell + 1] as usize] {
                            let p = self.roots[k as usize] + origin;
                            let w1 = (p - a).perp_dot(c - a) / den;
                            let w2 = (b - a).perp_dot(p - a) / den;
                            if w1 >= 0.0 && w2 >= 0.0 && w1 + w2 <= 1.0 {
                                f(k as usize, origin.x, origin.y);
                            }
                        }
                    }
                }
            }
        }
    }
}
