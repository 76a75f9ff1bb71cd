//! The fur composited into another picture of the same view (`Renderer::render_over`), on the
//! CPU adapter: the furred torus seen from above (orthographic), its occluders written from the
//! view's analytic depths, checked against the plain render and the torus's geometry.
#![cfg(feature = "render")]

mod common;

use std::sync::OnceLock;

use pelt::render::{Camera, Lighting, Occluders, RenderSettings, RgbaImage};

use common::torus::{FurredTorus, covered, differing};
use common::{look_at, orthographic, parameter_name};

const SIZE: u32 = 96;
/// Fur height, object units (the painted lengths are all 1).
const FUR_DEPTH: f32 = 0.08;
/// Half the side of the view, object units.
const HALF: f64 = 1.6;
/// The torus's radii (`pelt::mesh::shapes::torus`).
const MAJOR: f64 = 1.0;
const MINOR: f64 = 0.35;

fn fixture() -> &'static FurredTorus {
    static FIXTURE: OnceLock<FurredTorus> = OnceLock::new();
    FIXTURE.get_or_init(|| FurredTorus::new(32, 16, [6.0, 2.0], FUR_DEPTH))
}

/// Orthographic, looking down the torus's axis from z = 3: view depth `z_v = z − 3` maps to
/// window depth `−0.2 z_v − 0.1 = 0.5 − 0.2 z`.
fn top() -> Camera {
    Camera {
        view: look_at([0.0, 0.0, 3.0], [0.0, 1.0, 0.0]),
        projection: orthographic(HALF, 0.5, 5.5),
        width: SIZE,
        height: SIZE,
    }
}

fn window_depth(z: f64) -> f32 {
    (0.5 - 0.2 * z) as f32
}

/// The object-space point under pixel `(column, row)` of [`top`] (rows top first, +y up).
fn pixel_xy(column: u32, row: u32) -> (f64, f64) {
    let x = ((f64::from(column) + 0.5) / f64::from(SIZE) * 2.0 - 1.0) * HALF;
    let y = (1.0 - (f64::from(row) + 0.5) / f64::from(SIZE) * 2.0) * HALF;
    (x, y)
}

/// Per pixel of [`top`]: `depth(x, y)` (1 where it gives None).
fn depths(depth: impl Fn(f64, f64) -> Option<f32>) -> Vec<f32> {
    (0..SIZE)
        .flat_map(|row| (0..SIZE).map(move |column| (column, row)))
        .map(|(column, row)| {
            let (x, y) = pixel_xy(column, row);
            depth(x, y).unwrap_or(1.0)
        })
        .collect()
}

/// The top of a torus tube of radius `tube` around the ring, where the view meets it.
fn tube_top(x: f64, y: f64, tube: f64) -> Option<f64> {
    let off = (x * x + y * y).sqrt() - MAJOR;
    (off.abs() < tube).then(|| (tube * tube - off * off).sqrt())
}

fn settings() -> RenderSettings {
    RenderSettings::default()
}

fn render(occluders: Option<&Occluders>) -> RgbaImage {
    let f = fixture();
    let scene = f.scene();
    match occluders {
        None => f.render(&scene, &top(), &settings()),
        Some(o) => f
            .renderer
            .render_over(&scene, &top(), &Lighting::default(), &settings(), Some(o))
            .unwrap(),
    }
}

fn alpha(image: &RgbaImage, column: u32, row: u32) -> u8 {
    image.pixels[4 * (row * SIZE + column) as usize + 3]
}

#[test]
fn nothing_in_the_way_draws_the_plain_frame() {
    let occluders = Occluders {
        depth: vec![1.0; (SIZE * SIZE) as usize],
        bias: 0.0,
    };
    assert_eq!(render(Some(&occluders)).pixels, render(None).pixels);
}

#[test]
fn a_wall_in_front_hides_the_fur_behind_it_and_nothing_else() {
    // A wall at z = 1 (above the fur, which ends at 0.35 + 0.08) over the left half.
    let wall = depths(|x, _| (x < 0.0).then(|| window_depth(1.0)));
    let over = render(Some(&Occluders {
        depth: wall,
        bias: 0.0,
    }));
    let plain = render(None);
    assert!(covered(&plain) > 1000);
    for row in 0..SIZE {
        for column in 0..SIZE {
            let (x, _) = pixel_xy(column, row);
            let i = 4 * (row * SIZE + column) as usize;
            if x < 0.0 {
                assert_eq!(
                    alpha(&over, column, row),
                    0,
                    "pixel ({column}, {row}) behind the wall"
                );
            } else {
                assert_eq!(
                    over.pixels[i..i + 4],
                    plain.pixels[i..i + 4],
                    "pixel ({column}, {row})"
                );
            }
        }
    }
}

#[test]
fn the_furs_own_hull_hides_it_only_without_the_bias() {
    // The outer shell drawn opaque by the other renderer (as Blender draws Pelt's shells): the
    // torus of tube radius `MINOR + h`, every fur fragment at or below it.
    let h = f64::from(FUR_DEPTH);
    let hull = depths(|x, y| tube_top(x, y, MINOR + h).map(window_depth));
    let plain = render(None);
    let kept = render(Some(&Occluders {
        depth: hull.clone(),
        bias: 2.0 * FUR_DEPTH,
    }));
    let hidden = render(Some(&Occluders {
        depth: hull,
        bias: 0.0,
    }));
    // Pushed back by twice the fur's height, the hull hides nothing where the tube faces the view
    // within 45° (there the hull is at most 1.5 fur heights above the skin along the view);
    // toward the tube's silhouettes the view runs through more of the hull and the bias no
    // longer covers it.
    let mut facing = 0;
    for row in 0..SIZE {
        for column in 0..SIZE {
            let (x, y) = pixel_xy(column, row);
            let off = (x * x + y * y).sqrt() - MAJOR;
            if off.abs() < MINOR * 0.7 {
                facing += 1;
                let i = 4 * (row * SIZE + column) as usize;
                let (a, b) = (&kept.pixels[i..i + 4], &plain.pixels[i..i + 4]);
                assert!(
                    a.iter().zip(b).all(|(p, q)| p.abs_diff(*q) <= 2),
                    "pixel ({column}, {row}): {a:?} vs {b:?}"
                );
            }
        }
    }
    assert!(facing > 500);
    assert!(differing(&kept, &plain, 2) < 0.15);
    // At its own depth, it hides the fur and the skin (all of them below it).
    assert!(
        covered(&hidden) * 20 < covered(&plain),
        "{} of {} pixels still covered",
        covered(&hidden),
        covered(&plain)
    );
}

#[test]
fn a_floor_through_the_tube_hides_what_is_below_it() {
    // A floor at z = 0.31, below the tube's crest (0.35): the fur of the tube's sides, whose tips
    // are below it, is hidden; the crest, above it with all its fur, draws as without the floor.
    let floor = MINOR - 0.5 * f64::from(FUR_DEPTH);
    let over = render(Some(&Occluders {
        depth: depths(|_, _| Some(window_depth(floor))),
        bias: 0.0,
    }));
    let plain = render(None);
    // The mesh's faces lie inside the analytic torus by up to about 0.007 (its chords).
    let margin = 0.02;
    let (mut sides, mut crest) = (0, 0);
    for row in 0..SIZE {
        for column in 0..SIZE {
            let (x, y) = pixel_xy(column, row);
            let Some(skin) = tube_top(x, y, MINOR) else {
                continue;
            };
            let i = 4 * (row * SIZE + column) as usize;
            if skin + f64::from(FUR_DEPTH) < floor - margin {
                sides += 1;
                assert_eq!(
                    alpha(&over, column, row),
                    0,
                    "pixel ({column}, {row}): fur below the floor"
                );
            } else if skin - margin > floor {
                crest += 1;
                assert_eq!(
                    over.pixels[i..i + 4],
                    plain.pixels[i..i + 4],
                    "pixel ({column}, {row}) on the crest"
                );
            }
        }
    }
    assert!(
        sides > 100 && crest > 20,
        "{sides} side pixels, {crest} crest pixels"
    );
}

#[test]
fn occluders_that_do_not_fit_the_frame_are_named() {
    let f = fixture();
    let scene = f.scene();
    let bad = |occluders: Occluders| {
        parameter_name(
            f.renderer
                .render_over(
                    &scene,
                    &top(),
                    &Lighting::default(),
                    &settings(),
                    Some(&occluders),
                )
                .unwrap_err(),
        )
    };
    let pixels = (SIZE * SIZE) as usize;
    assert_eq!(
        bad(Occluders {
            depth: vec![1.0; pixels - 1],
            bias: 0.0
        }),
        "occluders.depth"
    );
    let mut nan = vec![1.0; pixels];
    nan[7] = f32::NAN;
    assert_eq!(
        bad(Occluders {
            depth: nan,
            bias: 0.0
        }),
        "occluders.depth"
    );
    assert_eq!(
        bad(Occluders {
            depth: vec![1.0; pixels],
            bias: f32::INFINITY
        }),
        "occluders.bias"
    );
    assert_eq!(
        bad(Occluders {
            depth: vec![1.0; pixels],
            bias: -1.0
        }),
        "occluders.bias"
    );
}
