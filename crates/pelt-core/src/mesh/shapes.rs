//! Procedural meshes for tests and benchmarks (no file I/O needed to exercise the pipeline).

use glam::Vec3;

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

/// A UV sphere of radius 1 around the origin: `segments` meridians, `rings` bands of latitude
/// (`rings >= 2`, `segments >= 3`), single pole vertices with triangle fans, quads split into two
/// triangles; counter-clockwise seen from outside. Triangle order: north fan, the quad bands from
/// north to south (two triangles per quad), south fan; [`uv_sphere_polygons`] gives the quads.
pub fn uv_sphere(segments: usize, rings: usize) -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
    let (segments, rings) = (segments.max(3), rings.max(2));
    let mut positions = vec![[0.0, 0.0, 1.0]];
    for r in 1..rings {
        let theta = std::f64::consts::PI * r as f64 / rings as f64;
        for s in 0..segments {
            let phi = std::f64::consts::TAU * s as f64 / segments as f64;
            positions.push([
                (theta.sin() * phi.cos()) as f32,
                (theta.sin() * phi.sin()) as f32,
                theta.cos() as f32,
            ]);
        }
    }
    positions.push([0.0, 0.0, -1.0]);
    let south = (positions.len() - 1) as u32;
    let ring = |r: usize, s: usize| (1 + (r - 1) * segments + s % segments) as u32;
    let mut triangles = Vec::with_capacity(2 * segments * (rings - 1));
    for s in 0..segments {
        triangles.push([0, ring(1, s), ring(1, s + 1)]);
    }
    for r in 1..rings - 1 {
        for s in 0..segments {
            let (a, b, c, d) = (ring(r, s), ring(r + 1, s), ring(r + 1, s + 1), ring(r, s + 1));
            triangles.push([a, b, c]);
            triangles.push([a, c, d]);
        }
    }
    for s in 0..segments {
        triangles.push([south, ring(rings - 1, s + 1), ring(rings - 1, s)]);
    }
    (positions, triangles)
}

/// Polygon index per triangle of [`uv_sphere`]: one per fan triangle, one per quad.
pub fn uv_sphere_polygons(segments: usize, rings: usize) -> Vec<u32> {
    let (segments, rings) = (segments.max(3), rings.max(2));
    let quads = segments * (rings - 2);
    let mut polygons: Vec<u32> = (0..segments as u32).collect();
    polygons.extend((0..2 * quads).map(|t| (segments + t / 2) as u32));
    polygons.extend((0..segments).map(|s| (segments + quads + s) as u32));
    polygons
}

/// The square `[-1, 1]²` in the xy plane (facing +z) as `n × n` quads (`n >= 1`), each split
/// along its diagonal from `(i, j)` to `(i + 1, j + 1)`; vertex `(i, j)` is `j (n + 1) + i`. An
/// open mesh: its four sides are its border.
pub fn square(n: usize) -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
    let n = n.max(1);
    let at = |k: usize| k as f32 / n as f32 * 2.0 - 1.0;
    let positions = (0..=n)
        .flat_map(|j| (0..=n).map(move |i| [at(i), at(j), 0.0]))
        .collect();
    let v = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    let triangles = (0..n)
        .flat_map(|j| (0..n).map(move |i| (i, j)))
        .flat_map(|(i, j)| {
            [
                [v(i, j), v(i + 1, j), v(i + 1, j + 1)],
                [v(i, j), v(i + 1, j + 1), v(i, j + 1)],
            ]
        })
        .collect();
    (positions, triangles)
}

/// The cube `[-1, 1]³` with `n × n` quads per side (`n >= 1`); vertices on the cube's edges are
/// shared, so the mesh is closed with sharp 90° edges.
pub fn cube(n: usize) -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
    let n = n.max(1);
    let mut index = std::collections::HashMap::new();
    let mut positions = Vec::new();
    let mut vertex = |g: [usize; 3]| -> u32 {
        *index.entry(g).or_insert_with(|| {
            positions.push(g.map(|c| 2.0 * c as f32 / n as f32 - 1.0));
            (positions.len() - 1) as u32
        })
    };
    let mut triangles = Vec::with_capacity(12 * n * n);
    // (axis fixed, its value, the two running axes ordered so that a × b points outwards)
    let sides = [
        (0, n, 1, 2),
        (0, 0, 2, 1),
        (1, n, 2, 0),
        (1, 0, 0, 2),
        (2, n, 0, 1),
        (2, 0, 1, 0),
    ];
    for (fixed, value, a, b) in sides {
        for i in 0..n {
            for j in 0..n {
                let mut corner = |di: usize, dj: usize| {
                    let mut g = [0; 3];
                    g[fixed] = value;
                    g[a] = i + di;
                    g[b] = j + dj;
                    vertex(g)
                };
                let (p, q, r, s) = (corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1));
                triangles.push([p, q, r]);
                triangles.push([p, r, s]);
            }
        }
    }
    (positions, triangles)
}

/// A [`uv_sphere`] with three round holes (triangles whose centroid lies within 0.35 of three
/// points on the sphere are left out); the vertices inside the holes stay, unused.
pub fn sphere_with_holes(segments: usize, rings: usize) -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
    let (positions, mut triangles) = uv_sphere(segments, rings);
    let centres = [[1.0f32, 0.0, 0.0], [0.0, -0.8, 0.6], [-0.6, 0.0, -0.8]];
    triangles.retain(|t| {
        let c = centroid(&positions, t);
        centres
            .iter()
            .all(|h| (c - Vec3::from(*h)).length_squared() > 0.35 * 0.35)
    });
    (positions, triangles)
}

/// A [`uv_sphere`] and a [`torus`] side by side (two connected components).
pub fn two_components() -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
    let (mut positions, mut triangles) = uv_sphere(32, 16);
    let (torus_positions, torus_triangles) = torus(48, 16);
    let offset = positions.len() as u32;
    positions.extend(torus_positions.iter().map(|p| [p[0] + 3.0, p[1], p[2]]));
    triangles.extend(torus_triangles.iter().map(|t| t.map(|v| v + offset)));
    (positions, triangles)
}

/// A flat `n × n` grid on `[-1, 1]²` (z = 0, facing +Z) with a fin of `n/2` rows of quads standing
/// up along the grid line y = 0: every edge on that line has three faces (non-manifold).
pub fn fin(n: usize) -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
    let n = (n.max(2) / 2) * 2;
    let step = 2.0 / n as f32;
    let mut positions = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            positions.push([i as f32 * step - 1.0, j as f32 * step - 1.0, 0.0]);
        }
    }
    let grid = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    let mut triangles = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let (a, b, c, d) = (grid(i, j), grid(i + 1, j), grid(i + 1, j + 1), grid(i, j + 1));
            triangles.push([a, b, c]);
            triangles.push([a, c, d]);
        }
    }
    // Fin rows k = 1..=n/2 above the line j = n/2; row 0 is the grid line itself.
    let first = positions.len();
    for k in 1..=n / 2 {
        for i in 0..=n {
            positions.push([i as f32 * step - 1.0, 0.0, k as f32 * step]);
        }
    }
    let fin_vertex = |i: usize, k: usize| {
        if k == 0 {
            grid(i, n / 2)
        } else {
            (first + (k - 1) * (n + 1) + i) as u32
        }
    };
    for k in 0..n / 2 {
        for i in 0..n {
            let (a, b, c, d) = (
                fin_vertex(i, k),
                fin_vertex(i + 1, k),
                fin_vertex(i + 1, k + 1),
                fin_vertex(i, k + 1),
            );
            triangles.push([a, b, c]);
            triangles.push([a, c, d]);
        }
    }
    (positions, triangles)
}

/// A [`uv_sphere`] with zero-area triangles added: one with a repeated vertex per band and one
/// whose corners are collinear (an edge and its midpoint, a new vertex) per meridian.
pub fn with_zero_area_faces(segments: usize, rings: usize) -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
    let (mut positions, mut triangles) = uv_sphere(segments, rings);
    let original = triangles.len();
    for t in (0..original).step_by(segments.max(3)) {
        let [a, b, _] = triangles[t];
        triangles.push([a, a, b]);
    }
    for t in (segments.max(3)..original).step_by(7) {
        let [a, b, _] = triangles[t];
        let (pa, pb) = (positions[a as usize], positions[b as usize]);
        positions.push([
            (pa[0] + pb[0]) / 2.0,
            (pa[1] + pb[1]) / 2.0,
            (pa[2] + pb[2]) / 2.0,
        ]);
        triangles.push([a, (positions.len() - 1) as u32, b]);
    }
    (positions, triangles)
}

/// A [`torus`] whose minor radius ripples by ±25% (`sin 5u · sin 3v`): a smooth bumpy surface of
/// `2 × around × across` triangles for the large tests and benchmarks.
pub fn bumpy_torus(around: usize, across: usize) -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
    let (major, minor) = (1.0f64, 0.35f64);
    let tau = std::f64::consts::TAU;
    let (mut positions, triangles) = torus(around, across);
    for i in 0..around {
        let u = tau * i as f64 / around as f64;
        for j in 0..across {
            let v = tau * j as f64 / across as f64;
            let r = minor * (1.0 + 0.25 * (5.0 * u).sin() * (3.0 * v).sin());
            let ring = major + r * v.cos();
            positions[i * across + j] = [
                (ring * u.cos()) as f32,
                (ring * u.sin()) as f32,
                (r * v.sin()) as f32,
            ];
        }
    }
    (positions, triangles)
}

fn centroid(positions: &[[f32; 3]], t: &[u32; 3]) -> Vec3 {
    let [a, b, c] = t.map(|v| Vec3::from(positions[v as usize]));
    (a + b + c) / 3.0
}

/// Blender's Suzanne (507 vertices, 500 polygons fanned into 968 triangles), read from
/// `tests/data/suzanne.obj` at compile time: the demo's mesh, for benchmarks and tests.
pub fn suzanne() -> super::obj::MeshData {
    // The file ships with the crate and is checked by a test, so parsing cannot fail at run time.
    super::obj::parse_obj(include_str!("../../../../tests/data/suzanne.obj")).unwrap_or_default()
}

/// Splits every triangle into four at its edge midpoints, `levels` times (×4ⁿ triangles; shared
/// edges get one midpoint, so the result stays watertight where the input was). Each new triangle
/// is its own polygon. Colors are dropped.
pub fn subdivide(mesh: &super::obj::MeshData, levels: u32) -> super::obj::MeshData {
    let mut positions = mesh.positions.clone();
    let mut triangles = mesh.triangles.clone();
    for _ in 0..levels {
        let mut midpoints = std::collections::HashMap::with_capacity(triangles.len() * 2);
        let mut next = Vec::with_capacity(triangles.len() * 4);
        for &[a, b, c] in &triangles {
            let mut mid = |p: u32, q: u32| {
                *midpoints.entry((p.min(q), p.max(q))).or_insert_with(|| {
                    let (p, q) = (positions[p as usize], positions[q as usize]);
                    positions.push(std::array::from_fn(|k| 0.5 * (p[k] + q[k])));
                    positions.len() as u32 - 1
                })
            };
            let (ab, bc, ca) = (mid(a, b), mid(b, c), mid(c, a));
            next.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
        }
        triangles = next;
    }
    let polygons = (0..triangles.len() as u32).collect();
    super::obj::MeshData {
        positions,
        triangles,
        polygons,
        color: None,
    }
}
