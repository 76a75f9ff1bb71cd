//! Unit tests of `FurMesh`: every validation error, degenerate and non-manifold input, and the
//! derived data checked against hand-computed values.

use super::*;
use crate::error::{MeshError, PeltError};

fn octahedron() -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
    let p = vec![
        [1.0, 0.0, 0.0],
        [-1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.0, 0.0, -1.0],
    ];
    let t = vec![
        [0, 2, 4],
        [2, 1, 4],
        [1, 3, 4],
        [3, 0, 4],
        [2, 0, 5],
        [1, 2, 5],
        [3, 1, 5],
        [0, 3, 5],
    ];
    (p, t)
}

fn quad() -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
    let p = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]];
    (p, vec![[0, 1, 2], [0, 2, 3]])
}

fn mesh_err(input: MeshInput<'_>) -> MeshError {
    match FurMesh::new(input) {
        Err(PeltError::InvalidMesh(e)) => e,
        other => panic!("expected InvalidMesh, got {other:?}"),
    }
}

fn close(a: [f32; 3], b: [f32; 3], tol: f32) -> bool {
    (0..3).all(|k| (a[k] - b[k]).abs() <= tol)
}

#[test]
fn empty_vertices_and_empty_triangles_are_rejected() {
    let (p, t) = quad();
    assert_eq!(mesh_err(MeshInput::new(&[], &t)), MeshError::Empty("vertices"));
    assert_eq!(mesh_err(MeshInput::new(&p, &[])), MeshError::Empty("triangles"));
}

#[test]
fn nan_and_infinity_name_array_row_and_component() {
    let (mut p, t) = quad();
    p[2][1] = f32::NAN;
    match mesh_err(MeshInput::new(&p, &t)) {
        MeshError::NonFinite {
            array,
            row,
            component,
            value,
        } => {
            assert_eq!((array, row, component), ("positions", 2, 1));
            assert!(value.is_nan());
        }
        e => panic!("unexpected {e:?}"),
    }
    let (p, t) = quad();
    let mut comb = vec![[0.0f32; 3]; 4];
    comb[3][2] = f32::INFINITY;
    let e = mesh_err(MeshInput::new(&p, &t).with_comb(&comb));
    assert!(
        matches!(
            e,
            MeshError::NonFinite {
                array: "comb",
                row: 3,
                component: 2,
                ..
            }
        ),
        "{e:?}"
    );
    let mut color = vec![[1.0f32; 4]; 4];
    color[1][3] = f32::NEG_INFINITY;
    let e = mesh_err(MeshInput::new(&p, &t).with_color(&color));
    assert!(
        matches!(
            e,
            MeshError::NonFinite {
                array: "color",
                row: 1,
                component: 3,
                ..
            }
        ),
        "{e:?}"
    );
    let mut normals = vec![[0.0f32, 0.0, 1.0]; 4];
    normals[0][0] = f32::NAN;
    let e = mesh_err(MeshInput::new(&p, &t).with_normals(&normals));
    assert!(
        matches!(
            e,
            MeshError::NonFinite {
                array: "normals",
                row: 0,
                component: 0,
                ..
            }
        ),
        "{e:?}"
    );
    let length = [1.0, f32::NAN, 1.0, 1.0];
    let e = mesh_err(MeshInput::new(&p, &t).with_length(&length));
    assert!(
        matches!(
            e,
            MeshError::NonFinite {
                array: "length",
                row: 1,
                component: 0,
                ..
            }
        ),
        "{e:?}"
    );
}

#[test]
fn first_bad_row_is_reported_whatever_the_thread_count() {
    let p: Vec<[f32; 3]> = (0..100_000).map(|i| [i as f32, 0.0, 0.0]).collect();
    let mut bad = p.clone();
    bad[70_001][0] = f32::NAN;
    bad[90_000][0] = f32::NAN;
    let t = vec![[0, 1, 2]];
    for threads in [1, 2, 5] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let e = pool.install(|| super::validate::validate(&MeshInput::new(&bad, &t)));
        assert!(
            matches!(e, Err(MeshError::NonFinite { row: 70_001, .. })),
            "{e:?}"
        );
    }
}

#[test]
fn index_out_of_range_names_triangle_and_corner() {
    let (p, _) = quad();
    let t = vec![[0, 1, 2], [0, 2, 4]];
    assert_eq!(
        mesh_err(MeshInput::new(&p, &t)),
        MeshError::IndexOutOfRange {
            triangle: 1,
            corner: 2,
            index: 4,
            vertex_count: 4
        }
    );
}

#[test]
fn attribute_arrays_of_the_wrong_length_are_rejected() {
    let (p, t) = quad();
    let three3 = vec![[0.0f32; 3]; 3];
    let five4 = vec![[0.0f32; 4]; 5];
    let e = mesh_err(MeshInput::new(&p, &t).with_normals(&three3));
    assert_eq!(
        e,
        MeshError::AttributeLength {
            array: "normals",
            expected: 4,
            got: 3
        }
    );
    let e = mesh_err(MeshInput::new(&p, &t).with_color(&five4));
    assert_eq!(
        e,
        MeshError::AttributeLength {
            array: "color",
            expected: 4,
            got: 5
        }
    );
    let e = mesh_err(MeshInput::new(&p, &t).with_comb(&three3));
    assert_eq!(
        e,
        MeshError::AttributeLength {
            array: "comb",
            expected: 4,
            got: 3
        }
    );
    let e = mesh_err(MeshInput::new(&p, &t).with_length(&[1.0; 2]));
    assert_eq!(
        e,
        MeshError::AttributeLength {
            array: "length",
            expected: 4,
            got: 2
        }
    );
}

#[test]
fn length_outside_range_is_rejected_and_bounds_are_accepted() {
    let (p, t) = quad();
    let e = mesh_err(MeshInput::new(&p, &t).with_length(&[0.0, 1.0, -0.5, 1.0]));
    assert_eq!(
        e,
        MeshError::LengthOutOfRange {
            vertex: 2,
            value: -0.5,
            max: MAX_LENGTH
        }
    );
    let e = mesh_err(MeshInput::new(&p, &t).with_length(&[0.0, 1.0, 1.0, 1000.5]));
    assert!(matches!(e, MeshError::LengthOutOfRange { vertex: 3, .. }));
    let ok = FurMesh::new(MeshInput::new(&p, &t).with_length(&[0.0, MAX_LENGTH, 1.0, 0.5])).unwrap();
    assert_eq!(ok.length().unwrap()[1], MAX_LENGTH);
}

#[test]
fn zero_given_normal_is_rejected() {
    let (p, t) = quad();
    let normals = [[0.0, 0.0, 1.0], [0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 0.0, 1.0]];
    assert_eq!(
        mesh_err(MeshInput::new(&p, &t).with_normals(&normals)),
        MeshError::ZeroNormal { row: 1 }
    );
}

#[test]
fn error_messages_name_the_element() {
    let (p, _) = quad();
    let t = vec![[0, 1, 9]];
    let msg = FurMesh::new(MeshInput::new(&p, &t)).unwrap_err().to_string();
    assert!(
        msg.contains("triangle 0") && msg.contains("vertex 9") && msg.contains("4 vertices"),
        "{msg}"
    );
}

#[test]
fn closed_octahedron_statistics_match_euler() {
    let (p, t) = octahedron();
    let m = FurMesh::new(MeshInput::new(&p, &t)).unwrap();
    let s = m.stats();
    assert_eq!((s.vertices, s.faces, s.edges), (6, 8, 12));
    assert_eq!(
        s.vertices + s.faces - s.edges,
        2,
        "Euler characteristic of a sphere"
    );
    assert_eq!(
        (s.boundary_edges, s.non_manifold_edges, s.degenerate_faces),
        (0, 0, 0)
    );
    assert_eq!((s.components, s.loose_vertices), (1, 0));
    // 8 equilateral triangles of side sqrt(2): area 8 * sqrt(3)/4 * 2
    assert!(
        (s.surface_area - 4.0 * 3f64.sqrt()).abs() < 1e-6,
        "{}",
        s.surface_area
    );
    assert_eq!(s.bbox_min, [-1.0, -1.0, -1.0]);
    assert_eq!(s.bbox_max, [1.0, 1.0, 1.0]);
    assert!(m.topology().edges().iter().all(|e| e.face_count == 2));
}

#[test]
fn area_weighted_normals_of_octahedron_point_outward() {
    let (p, t) = octahedron();
    let m = FurMesh::new(MeshInput::new(&p, &t)).unwrap();
    assert!(!m.normals_given());
    for (n, p) in m.normals().iter().zip(&p) {
        assert!(close(*n, *p, 1e-6), "{n:?} vs {p:?}");
    }
}

#[test]
fn given_normals_are_normalized_not_recomputed() {
    let (p, t) = quad();
    let given = [
        [0.0, 0.0, 2.0],
        [0.0, 3.0, 0.0],
        [0.0, 0.0, -1.0],
        [1.0, 1.0, 0.0],
    ];
    let m = FurMesh::new(MeshInput::new(&p, &t).with_normals(&given)).unwrap();
    assert!(m.normals_given());
    let h = std::f32::consts::FRAC_1_SQRT_2;
    assert_eq!(m.normals()[0], [0.0, 0.0, 1.0]);
    assert_eq!(m.normals()[1], [0.0, 1.0, 0.0]);
    assert!(close(m.normals()[3], [h, h, 0.0], 1e-7));
}

#[test]
fn tangent_frames_are_orthonormal_and_right_handed() {
    let dirs: Vec<[f32; 3]> = (0..200)
        .map(|i| {
            let z = -1.0 + 2.0 * (i as f32 + 0.5) / 200.0;
            let phi = i as f32 * 2.399_963;
            let r = (1.0 - z * z).sqrt();
            [r * phi.cos(), r * phi.sin(), z]
        })
        .chain([[0.0, 0.0, 1.0], [0.0, 0.0, -1.0], [1.0, 0.0, 0.0]])
        .collect();
    for n in dirs {
        let [t, b] = orthonormal_basis(n).map(glam::Vec3::from);
        let v = glam::Vec3::from(n);
        assert!(
            (t.length_squared() - 1.0).abs() < 1e-5 && (b.length_squared() - 1.0).abs() < 1e-5,
            "{n:?}"
        );
        assert!(
            t.dot(v).abs() < 1e-5 && b.dot(v).abs() < 1e-5 && t.dot(b).abs() < 1e-5,
            "{n:?}"
        );
        let tb = t.as_dvec3().cross(b.as_dvec3()).as_vec3().to_array();
        assert!(close(tb, n, 1e-5), "not right-handed at {n:?}");
    }
}

#[test]
fn open_quad_has_boundary_edges_and_shared_diagonal() {
    let (p, t) = quad();
    let m = FurMesh::new(MeshInput::new(&p, &t)).unwrap();
    let s = m.stats();
    assert_eq!((s.edges, s.boundary_edges, s.non_manifold_edges), (5, 4, 0));
    assert!((s.surface_area - 1.0).abs() < 1e-9);
    let topo = m.topology();
    let diagonal = topo.find_edge(2, 0).expect("diagonal 0-2 exists");
    assert_eq!(topo.edges()[diagonal].faces, [0, 1]);
    assert_eq!(topo.edges()[diagonal].key, edge_key(2, 0));
    assert_eq!(topo.edges()[topo.find_edge(3, 2).unwrap()].key, (2u64 << 32) | 3);
    assert_eq!(
        topo.face_edges()[0][2],
        diagonal as u32,
        "side 2->0 of triangle 0"
    );
    assert_eq!(
        topo.face_edges()[1][0],
        diagonal as u32,
        "side 0->2 of triangle 1"
    );
    assert!(topo.find_edge(1, 3).is_none());
    assert_eq!(topo.vertex_faces(0), &[0, 1]);
    assert_eq!(topo.vertex_faces(1), &[0]);
}

#[test]
fn non_manifold_edges_are_counted() {
    // three triangles on the edge 0-1 (a "book" with three pages)
    let p = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.5, 1.0, 0.0],
        [0.5, -1.0, 0.0],
        [0.5, 0.0, 1.0],
    ];
    let t = vec![[0, 1, 2], [1, 0, 3], [0, 1, 4]];
    let m = FurMesh::new(MeshInput::new(&p, &t)).unwrap();
    let s = m.stats();
    assert_eq!((s.edges, s.non_manifold_edges, s.boundary_edges), (7, 1, 6));
    let e = m.topology().edges()[m.topology().find_edge(0, 1).unwrap()];
    assert_eq!((e.face_count, e.faces), (3, [0, 1]));
    assert!(m.normals().iter().flatten().all(|c| c.is_finite()));
}

#[test]
fn degenerate_triangles_are_counted_and_harmless() {
    let p = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [2.0, 0.0, 0.0], // collinear with 0 and 1
        [0.0, 1.0, 0.0],
        [5.0, 5.0, 5.0], // loose vertex
    ];
    let t = vec![[0, 1, 3], [0, 1, 2], [1, 1, 3], [3, 3, 3]];
    let m = FurMesh::new(MeshInput::new(&p, &t)).unwrap();
    let s = m.stats();
    assert_eq!(s.degenerate_faces, 3);
    assert_eq!(s.loose_vertices, 1);
    assert_eq!(s.components, 1);
    assert_eq!(m.topology().face_edges()[3], [NO_EDGE; 3]);
    assert_eq!(m.topology().face_edges()[2][0], NO_EDGE);
    // vertex 2 only touches a zero-area triangle: it still gets a finite unit normal
    let n2 = m.normals()[2];
    assert!((frames::norm(n2.map(f64::from)) - 1.0).abs() < 1e-6);
    assert!((s.surface_area - 0.5).abs() < 1e-9);
    assert!(
        m.tangents()
            .iter()
            .chain(m.bitangents())
            .flatten()
            .all(|c| c.is_finite())
    );
}

#[test]
fn separate_pieces_are_separate_components() {
    let (p, t) = octahedron();
    let mut p2 = p.clone();
    p2.extend(p.iter().map(|v| [v[0] + 5.0, v[1], v[2]]));
    let mut t2 = t.clone();
    t2.extend(t.iter().map(|f| [f[0] + 6, f[1] + 6, f[2] + 6]));
    let m = FurMesh::new(MeshInput::new(&p2, &t2)).unwrap();
    assert_eq!(m.stats().components, 2);
    assert_eq!(m.stats().edges, 24);
}

#[test]
fn build_is_identical_whatever_the_thread_count() {
    let (p, t) = shapes::torus(40, 30);
    let build = |threads| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| FurMesh::build(MeshInput::new(&p, &t)).unwrap())
    };
    let (a, b) = (build(1), build(4));
    assert_eq!(a.normals(), b.normals());
    assert_eq!(a.tangents(), b.tangents());
    assert_eq!(a.topology().edges(), b.topology().edges());
    assert_eq!(a.stats(), b.stats());
    assert_eq!(a.stats().surface_area.to_bits(), b.stats().surface_area.to_bits());
}

#[test]
fn torus_is_closed_with_euler_characteristic_zero() {
    let (p, t) = shapes::torus(40, 30);
    let m = FurMesh::new(MeshInput::new(&p, &t)).unwrap();
    let s = m.stats();
    assert_eq!(s.vertices as i64 - s.edges as i64 + s.faces as i64, 0);
    assert_eq!((s.boundary_edges, s.non_manifold_edges, s.components), (0, 0, 1));
    // analytic torus area 4 pi^2 R r with R = 1, r = 0.35; the polygon is slightly smaller
    let exact = 4.0 * std::f64::consts::PI.powi(2) * 0.35;
    assert!(
        (s.surface_area - exact).abs() / exact < 0.01,
        "{}",
        s.surface_area
    );
}

#[test]
fn polygon_array_must_have_one_row_per_triangle() {
    let (p, t) = quad();
    let m = FurMesh::new(MeshInput::new(&p, &t).with_polygons(&[7, 7])).unwrap();
    assert_eq!(m.polygons(), Some(&[7u32, 7][..]));
    assert_eq!(
        mesh_err(MeshInput::new(&p, &t).with_polygons(&[0])),
        MeshError::TriangleAttributeLength {
            array: "polygons",
            expected: 2,
            got: 1
        }
    );
}

#[test]
fn vertex_components_label_each_piece_and_skip_loose_vertices() {
    let (mut p, mut t) = quad();
    p.extend([[5.0, 0.0, 0.0], [6.0, 0.0, 0.0], [5.0, 1.0, 0.0], [9.0, 9.0, 9.0]]);
    t.push([4, 5, 6]);
    let m = FurMesh::new(MeshInput::new(&p, &t)).unwrap();
    assert_eq!(
        m.topology().vertex_components(),
        vec![0, 0, 0, 0, 1, 1, 1, NO_COMPONENT]
    );
}

/// V − E + F, boundary and non-manifold edges, components and degenerate faces of a shape.
fn topology_of(shape: (Vec<[f32; 3]>, Vec<[u32; 3]>)) -> (i64, usize, usize, usize, usize) {
    let (p, t) = shape;
    let m = FurMesh::new(MeshInput::new(&p, &t)).unwrap();
    let s = m.stats();
    let used = s.vertices - m.topology().loose_vertices();
    (
        used as i64 - s.edges as i64 + s.faces as i64,
        s.boundary_edges,
        s.non_manifold_edges,
        s.components,
        s.degenerate_faces,
    )
}

#[test]
fn test_shapes_have_the_topology_they_promise() {
    // Closed genus-0 surfaces: χ = 2, no boundary.
    assert_eq!(topology_of(shapes::uv_sphere(16, 8)), (2, 0, 0, 1, 0));
    assert_eq!(topology_of(shapes::cube(4)), (2, 0, 0, 1, 0));
    // Closed genus 1.
    assert_eq!(topology_of(shapes::bumpy_torus(24, 12)), (0, 0, 0, 1, 0));
    // Three holes in a sphere: χ = 2 − 3, with boundary edges.
    let (chi, boundary, _, components, _) = topology_of(shapes::sphere_with_holes(48, 24));
    assert_eq!((chi, components), (-1, 1));
    assert!(boundary > 0);
    // A sphere and a torus.
    assert_eq!(topology_of(shapes::two_components()), (2, 0, 0, 2, 0));
    // The fin's foot: n edges with three faces each.
    let (_, _, non_manifold, components, _) = topology_of(shapes::fin(8));
    assert_eq!((non_manifold, components), (8, 1));
    // Zero-area triangles added to a sphere.
    let (_, _, _, _, degenerate) = topology_of(shapes::with_zero_area_faces(16, 8));
    assert!(degenerate >= 14, "{degenerate}");
    // One polygon index per triangle; fans are single triangles, the rest quads.
    let polygons = shapes::uv_sphere_polygons(16, 8);
    assert_eq!(polygons.len(), shapes::uv_sphere(16, 8).1.len());
    assert_eq!(
        *polygons.iter().max().unwrap_or(&0) as usize + 1,
        16 + 16 * 6 + 16
    );
}
