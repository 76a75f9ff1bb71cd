//! Fin quads and shell offsets against the square's geometry and the offset formula written out.

use super::fin_quads;
use crate::mesh::shell_offset::{growth, lifted, shell_layer};
use crate::mesh::uv_split::tests::square;

#[test]
fn one_fin_per_edge_standing_on_it() {
    let mesh = square();
    let fins = fin_quads(&mesh, 0.5);
    assert_eq!(fins.len(), 5);
    let edges = mesh.topology().edges();
    for (k, quad) in fins.iter().enumerate() {
        assert_eq!(quad.edge as usize, k);
        assert_eq!(quad.vertices, edges[k].vertices());
        let [a, b] = quad.vertices.map(|v| mesh.positions()[v as usize]);
        let e = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let len = (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]).sqrt();
        let f = quad.normal;
        // The fin stands on the edge along the (flat) normal +z: its normal is in the plane,
        // perpendicular to the edge.
        assert!(
            (f[0] * e[0] + f[1] * e[1]).abs() < 1e-6 && f[2].abs() < 1e-6,
            "{f:?}"
        );
        assert!(((f[0] * f[0] + f[1] * f[1]).sqrt() - 1.0).abs() < 1e-6);
        assert_eq!(quad.center, [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0, 0.0]);
        // The texture interval is the edge length in tile units, starting in [0, 1).
        assert!((0.0..1.0).contains(&quad.u0));
        assert!((quad.u1 - quad.u0 - 0.5 * f64::from(len)).abs() < 1e-6);
    }
}

#[test]
fn shells_lift_along_the_combed_normal() {
    // Normal +z, comb (1, 0, 0.5): its tangential part (1, 0, 0) shears the growth direction.
    let g = growth([0.0, 0.0, 1.0], [1.0, 0.0, 0.5]);
    assert_eq!(g, [1.0, 0.0, 1.0]);
    // Layer 3 of spacing 1/8 at fur depth 0.4 and length 0.5: 3/8 · 0.4 · 0.5 = 0.075 along g.
    let p = lifted(
        [1.0, 2.0, 3.0],
        [0.0, 0.0, 1.0],
        [1.0, 0.0, 0.5],
        3.0 / 8.0,
        0.4,
        0.5,
    );
    for (got, want) in p.iter().zip([1.075f32, 2.0, 3.075]) {
        assert!((got - want).abs() < 1e-6, "{p:?}");
    }
}

#[test]
fn shell_layers_round_evenly_over_the_stack() {
    // Every layer above the skin once when shells = layers − 1.
    assert_eq!(
        (1..=15).map(|s| shell_layer(s, 15, 16)).collect::<Vec<_>>(),
        (1..=15).collect::<Vec<_>>()
    );
    // 4 shells of 16 layers: round(s · 15 / 4) = 4, 8, 11, 15 (7.5 and 3.75 round up).
    assert_eq!(
        (1..=4).map(|s| shell_layer(s, 4, 16)).collect::<Vec<_>>(),
        [4, 8, 11, 15]
    );
    // More shells than layers repeat layers: round(s · 2 / 4) = 1, 1, 2, 2 (0.5 rounds up).
    assert_eq!(
        (1..=4).map(|s| shell_layer(s, 4, 3)).collect::<Vec<_>>(),
        [1, 1, 2, 2]
    );
}
