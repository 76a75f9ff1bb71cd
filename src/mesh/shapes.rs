//! Procedural meshes for tests and benchmarks (no file I/O needed to exercise the pipeline).

/// A closed torus (major radius 1, minor radius 0.35) in the XY plane with `around × across` quads
/// split into `2 × around × across` triangles, counter-clockwise seen from outside.
pub fn torus(around: usize, across: usize) -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
    let (major, minor) = (1.0f32, 0.35f32);
    let tau = std::f32::consts::TAU;
    let mut positions = Vec::with_capacity(around * across);
    for i in 0..around {
        let u = tau * i as f32 / around as f32;
        for j in 0..across {
            let v = tau * j as f32 / across as f32;
            let r = major + minor * v.cos();
            positions.push([r * u.cos(), r * u.sin(), minor * v.sin()]);
        }
    }
    let index = |i: usize, j: usize| ((i % around) * across + (j % across)) as u32;
    let mut triangles = Vec::with_capacity(2 * around * across);
    for i in 0..around {
        for j in 0..across {
            let (a, b, c, d) = (index(i, j), index(i + 1, j), index(i + 1, j + 1), index(i, j + 1));
            triangles.push([a, b, c]);
            triangles.push([a, c, d]);
        }
    }
    (positions, triangles)
}

/// Per-corner UVs of [`torus`]`(around, across)`: the parametric angles scaled to `repeats` tiles
/// around the ring and around the tube (`uvs[f][k]` for corner `k` of triangle `f`). The quads
/// that close the ring and the tube take the end of the range (`repeats`, not 0), so the UVs jump
/// there like at a seam between texture patches.
pub fn torus_uvs(around: usize, across: usize, repeats: [f32; 2]) -> Vec<[[f32; 2]; 3]> {
    let uv = |i: usize, j: usize| {
        [
            repeats[0] * i as f32 / around as f32,
            repeats[1] * j as f32 / across as f32,
        ]
    };
    let mut uvs = Vec::with_capacity(2 * around * across);
    for i in 0..around {
        for j in 0..across {
            uvs.push([uv(i, j), uv(i + 1, j), uv(i + 1, j + 1)]);
            uvs.push([uv(i, j), uv(i + 1, j + 1), uv(i, j + 1)]);
        }
    }
    uvs
}
