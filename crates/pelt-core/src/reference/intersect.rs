//! Ray tests against the two primitives of the reference: a tapered hair segment and a skin
//! triangle.

use glam::Vec3A;

/// Where a ray meets a hair segment.
#[derive(Debug, Clone, Copy)]
pub(crate) struct SegmentHit {
    /// Ray parameter where the ray enters the hair.
    pub t: f32,
    /// Place along the segment, `[0, 1]`.
    pub s: f32,
}

/// A hair segment from `a` to `b` with radius `ra` at `a` and `rb` at `b`, linear between.
#[derive(Debug, Clone, Copy)]
pub(crate) struct HairSegment {
    pub a: Vec3A,
    pub b: Vec3A,
    pub ra: f32,
    pub rb: f32,
}

/// A ray (`origin + t · direction`, `direction` unit) against a hair segment: a hit where the ray passes the segment's axis closer than the radius there, which
/// is exact for a cylinder (its silhouette from any direction is its radius from the axis); the
/// taper is taken at the point of closest approach. The hit's `t` is where the ray enters the
/// cylinder. A ray along the axis never hits (the segment's caps are inside its neighbours).
#[inline]
pub(crate) fn ray_segment(
    origin: Vec3A,
    direction: Vec3A,
    segment: &HairSegment,
    t_min: f32,
    t_max: f32,
) -> Option<SegmentHit> {
    let HairSegment { a, b, ra, rb } = *segment;
    let u = b - a;
    let w = origin - a;
    let du = direction.dot(u);
    let uu = u.dot(u);
    let dw = direction.dot(w);
    let uw = u.dot(w);
    let den = uu - du * du;
    if den.is_nan() || den <= 1e-12 * uu {
        return None;
    }
    let s = (uw - du * dw) / den;
    if !(0.0..=1.0).contains(&s) {
        return None;
    }
    let t = (du * uw - uu * dw) / den;
    let r = ra + s * (rb - ra);
    let gap = origin + t * direction - (a + s * u);
    let d2 = gap.length_squared();
    if d2 >= r * r {
        return None;
    }
    // sin of the angle between the ray and the axis: the chord through the cylinder is
    // 2 √(r² − d²) / sin.
    let sin = (den / uu).sqrt().max(1e-3);
    let t = t - (r * r - d2).sqrt() / sin;
    (t > t_min && t < t_max).then_some(SegmentHit { t, s })
}

/// Where a ray meets a triangle: its parameter and the barycentric weights of the 2nd and 3rd
/// corner.
#[derive(Debug, Clone, Copy)]
pub(crate) struct TriangleHit {
    pub t: f32,
    pub b1: f32,
    pub b2: f32,
}

/// Möller–Trumbore, both faces.
#[inline]
pub(crate) fn ray_triangle(
    origin: Vec3A,
    direction: Vec3A,
    p: [Vec3A; 3],
    t_min: f32,
    t_max: f32,
) -> Option<TriangleHit> {
    let e1 = p[1] - p[0];
    let e2 = p[2] - p[0];
    let q = direction.cross(e2);
    let det = e1.dot(q);
    if det.abs() < 1e-20 {
        return None;
    }
    let inv = 1.0 / det;
    let s = origin - p[0];
    let b1 = s.dot(q) * inv;
    if !(0.0..=1.0).contains(&b1) {
        return None;
    }
    let r = s.cross(e1);
    let b2 = direction.dot(r) * inv;
    if !(b2 >= 0.0 && b1 + b2 <= 1.0) {
        return None;
    }
    let t = e2.dot(r) * inv;
    (t > t_min && t < t_max).then_some(TriangleHit { t, b1, b2 })
}
