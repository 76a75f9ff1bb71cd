//! Bench cases of the reference renderer.

use std::time::Instant;

use super::{BenchOptions, CaseResult, time_once};
use pelt_core::error::Result;
use pelt_core::hair::grow_strands;
use pelt_core::lapped::build_patches;
use pelt_core::reference::scenes::{FurLength, LightSetup, Shape, canonical_scene};
use pelt_core::reference::{FurGeometry, ReferenceScene, ReferenceSettings, render_reference};

/// `reference.render`: the canonical sphere (short fur, side light) at 512² converged to 1%
/// relative standard error of its mean radiance, placing the strands and building the BVH
/// included (`reference.scene` times those alone); median of three runs, peak memory of the
/// first.
pub(super) fn reference_render(options: &BenchOptions) -> Result<Vec<CaseResult>> {
    let side = if options.quick { 128 } else { 512 };
    let scene = canonical_scene(Shape::Sphere, FurLength::Short, LightSetup::Side, side)?;
    let strands = grow_strands(&scene.params.grown_hair(&scene.mesh))?;
    let patches = build_patches(&scene.mesh, &scene.params.patches)?;
    let fur_depth = scene.params.fur_depth();
    let settings = ReferenceSettings::default();
    let run = || {
        let start = Instant::now();
        let geometry = FurGeometry::from_bake(&scene.mesh, &patches, &strands, fur_depth)?;
        let traced = ReferenceScene::new(geometry)?;
        let prepared = start.elapsed().as_secs_f64();
        let image = render_reference(&traced, &scene.camera, &scene.lights, &settings, None)?;
        Ok((image, prepared, traced.strand_count()))
    };
    // The first run measures the peak; the seconds are the median of three (one in `--quick`).
    let ((image, prepared, strand_count), (first, peak)) = time_once(run)?;
    let mut seconds = vec![first];
    let mut placing = vec![prepared];
    for _ in 1..if options.quick { 1 } else { 3 } {
        let ((_, prepared, _), (s, _)) = time_once(run)?;
        seconds.push(s);
        placing.push(prepared);
    }
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let timing = (median(&mut seconds), peak);
    let prepared = median(&mut placing);
    let mut render = CaseResult::timed(
        "reference.render",
        format!(
            "{}, {side}x{side}, {strand_count} strands, {} samples/pixel",
            scene.name, image.samples
        ),
        timing,
    );
    render.error = Some(image.relative_error);
    render.error_metric = Some(format!(
        "relative standard error of the mean radiance (per-pixel {:.3})",
        image.pixel_error
    ));
    let place = CaseResult::timed(
        "reference.scene",
        format!("{}: strands placed and BVH built", scene.name),
        (prepared, None),
    );
    Ok(vec![render, place])
}
