//! The bounding sphere of a set of positions, which the renderer's LOD schedule and the
//! viewer's orbit camera share.

use glam::{DVec3, Vec3};

/// The sphere around the axis-aligned box of `positions`, in f64: its centre is the box's, its
/// radius the distance from there to the farthest position. No positions give the origin and 0.
///
/// Not the smallest enclosing sphere, but cheap and stable: a pose that moves the vertices
/// moves it continuously.
pub fn bounding_sphere(positions: &[[f32; 3]]) -> (DVec3, f64) {
    if positions.is_empty() {
        return (DVec3::ZERO, 0.0);
    }
    let wide = |p: &[f32; 3]| Vec3::from(*p).as_dvec3();
    let (lo, hi) = positions
        .iter()
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(wide(p)), hi.max(wide(p)))
        });
    let centre = 0.5 * (lo + hi);
    let radius = positions
        .iter()
        .fold(0.0f64, |r, p| r.max(wide(p).distance(centre)));
    (centre, radius)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sphere_is_centred_on_the_box_and_reaches_the_farthest_point() {
        let points = [
            [0.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [0.0, 4.0, 0.0],
            [1.0, 1.0, -2.0],
        ];
        let (centre, radius) = bounding_sphere(&points);
        // Box [0, 2] × [0, 4] × [−2, 0], centre (1, 2, −1); the points lie √6, √6, √6 and √2 from it.
        assert_eq!(centre, DVec3::new(1.0, 2.0, -1.0));
        assert!((radius - 6f64.sqrt()).abs() < 1e-12);
        assert_eq!(
            bounding_sphere(&[[3.0, -1.0, 0.5]]),
            (DVec3::new(3.0, -1.0, 0.5), 0.0)
        );
        assert_eq!(bounding_sphere(&[]), (DVec3::ZERO, 0.0));
    }
}
