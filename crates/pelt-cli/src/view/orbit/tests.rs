use super::*;
use glam::{DMat4, Mat4};

/// `p` in normalized device coordinates (after the perspective divide).
fn view_proj(camera: &Camera, p: DVec3) -> DVec3 {
    let m = |a: &[f32; 16]| -> DMat4 { Mat4::from_cols_array(a).as_dmat4() };
    (m(&camera.projection) * m(&camera.view)).project_point3(p)
}

fn sphere() -> Sphere {
    Sphere {
        centre: DVec3::new(1.0, -2.0, 0.5),
        radius: 2.0,
    }
}

#[test]
fn the_bounding_sphere_holds_every_point_and_the_fur() {
    let points = [
        [0.0, 0.0, 0.0],
        [2.0, 0.0, 0.0],
        [0.0, 4.0, 0.0],
        [1.0, 1.0, -2.0],
    ];
    let s = Sphere::around(&points, 0.5);
    // Box [0, 2] × [0, 4] × [−2, 0], centre (1, 2, −1); the points lie √6, √6, √6 and √2 from it.
    assert_eq!(s.centre, DVec3::new(1.0, 2.0, -1.0));
    assert!((s.radius - (6f64.sqrt() + 0.5)).abs() < 1e-12);
    assert_eq!(Sphere::around(&[], 0.0).radius, 1.0);
}

#[test]
fn the_start_view_looks_at_the_centre_from_the_front_and_above() {
    let s = sphere();
    let camera = Orbit::default().camera(&s, 64, 64);
    let c = view_proj(&camera, s.centre);
    assert!(c[0].abs() < 1e-6 && c[1].abs() < 1e-6, "centre projects to {c:?}");
    assert!((0.0..1.0).contains(&c[2]));
    // A point in front of the centre (toward −Y, the front) is nearer: smaller depth.
    let front = view_proj(&camera, s.centre - 0.5 * DVec3::Y);
    assert!(front[2] < c[2]);
    // +Z is up on screen.
    let above = view_proj(&camera, s.centre + 0.5 * DVec3::Z);
    assert!(above[1] > 0.0);
}

#[test]
fn the_whole_sphere_is_in_view_at_every_aspect_and_angle() {
    let s = sphere();
    for (w, h) in [(64, 64), (200, 50), (50, 200)] {
        for (yaw, pitch) in [(0.0, 0.0), (1.0, 0.8), (4.0, -1.5)] {
            let orbit = Orbit {
                yaw,
                pitch,
                zoom: 1.0,
            };
            let camera = orbit.camera(&s, w, h);
            // Points of the sphere's surface in many directions.
            for i in 0..200 {
                let z = 1.0 - 2.0 * (f64::from(i) + 0.5) / 200.0;
                let a = f64::from(i) * 2.399_963;
                let r = (1.0 - z * z).sqrt();
                let p = s.centre + s.radius * DVec3::new(r * a.cos(), r * a.sin(), z);
                let c = view_proj(&camera, p);
                assert!(
                    c.is_finite()
                        && c[0].abs() <= 1.0 + 1e-6
                        && c[1].abs() <= 1.0 + 1e-6
                        && (-1e-6..=1.0 + 1e-6).contains(&c[2]),
                    "{w}x{h}, yaw {yaw}, pitch {pitch}: {p:?} projects to {c:?}"
                );
            }
        }
    }
}

#[test]
fn dragging_and_zooming_stay_in_range() {
    let mut orbit = Orbit::default();
    orbit.rotate(0.0, 1e6);
    assert!((orbit.pitch - MAX_PITCH).abs() < 1e-12);
    orbit.rotate(-100.0, 0.0);
    assert!((orbit.yaw - 1.0).abs() < 1e-12);
    for _ in 0..100 {
        orbit.zoom_by(1.0);
    }
    assert_eq!(orbit.zoom, ZOOM.0);
    orbit.zoom_by(-1.0);
    assert!((orbit.zoom - ZOOM.0 * ZOOM_STEP).abs() < 1e-12);
}

#[test]
fn light_angles_round_trip_a_direction() {
    let d = [0.4f32, -0.5, 0.75];
    let len = d.iter().map(|v| v * v).sum::<f32>().sqrt();
    let back = Angles::of(d).direction();
    for k in 0..3 {
        assert!((back[k] - d[k] / len).abs() < 1e-6, "{back:?}");
    }
    // Yaw 0 points toward −Y; a quarter turn toward +X; pitch up is +Z.
    let quarter = Angles {
        yaw: std::f64::consts::FRAC_PI_2,
        pitch: 0.0,
    };
    let e = quarter.direction();
    assert!((e[0] - 1.0).abs() < 1e-6 && e[1].abs() < 1e-6 && e[2].abs() < 1e-6);
    let mut up = Angles { yaw: 0.0, pitch: 0.0 };
    up.rotate(0.0, -1e6);
    assert!((up.direction()[2] - 1.0).abs() < 1e-6);
}
