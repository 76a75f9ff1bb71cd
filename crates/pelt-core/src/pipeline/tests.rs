use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};

use super::*;
use crate::mesh::shapes::uv_sphere;
use crate::{FurMesh, MeshInput};

/// A small sphere with color, comb and length, and the vertex count.
fn sphere(color: [f32; 4], comb: [f32; 3], length: f32) -> Arc<FurMesh> {
    let (positions, triangles) = uv_sphere(16, 8);
    let n = positions.len();
    let (color, comb, length) = (vec![color; n], vec![comb; n], vec![length; n]);
    let input = MeshInput::new(&positions, &triangles)
        .with_color(&color)
        .with_comb(&comb)
        .with_length(&length);
    Arc::new(FurMesh::new(input).unwrap())
}

fn small_params() -> BakeParams {
    let mut params = BakeParams::default();
    params.patches.tile_size = 0.5;
    params.hair.density = 300;
    params.volume.layers = 4;
    params.volume.resolution = 16;
    params.volume.fin_size = [32, 8];
    let mut transfer = TransferChoice::default();
    transfer.params.directions = 32;
    transfer.params.order = 2;
    transfer.auto = false;
    params.transfer = Some(transfer);
    params
}

fn ran(asset: &FurAsset) -> Vec<(&str, bool)> {
    asset.report.iter().map(|s| (s.stage.as_str(), s.ran)).collect()
}

const RED: [f32; 4] = [1.0, 0.0, 0.0, 1.0];
const DOWN: [f32; 3] = [0.0, 0.0, -1.0];

#[test]
fn first_bake_runs_every_stage_and_matches_the_stages_run_alone() {
    let params = small_params();
    let mesh = sphere(RED, DOWN, 1.0);
    let asset = Pipeline::new().bake(mesh.clone(), &params, None).unwrap();
    assert_eq!(
        ran(&asset),
        [("patches", true), ("volume", true), ("transfer", true)]
    );
    assert_eq!(
        *asset.patches,
        lapped::build_patches(&mesh, &params.patches).unwrap()
    );
    let volume = bake_volume(&params.grown_hair(&mesh), &params.volume, None).unwrap();
    assert_eq!(asset.volume.shells, volume.shells);
    let transfer = asset.transfer.as_ref().unwrap();
    assert_eq!(transfer.transfer.order, 2);
    assert_eq!(transfer.depth_in_tiles, 1.0);
    assert!(
        asset
            .report
            .iter()
            .all(|s| s.seconds >= 0.0 && !s.summary.is_empty())
    );
}

#[test]
fn a_rebake_runs_only_the_stages_whose_inputs_changed() {
    let mut pipeline = Pipeline::new();
    let params = small_params();
    let first = pipeline.bake(sphere(RED, DOWN, 1.0), &params, None).unwrap();

    // Same inputs, and a new color or a new (non-zero) length: nothing runs, results are shared.
    for mesh in [
        sphere(RED, DOWN, 1.0),
        sphere([0.0, 1.0, 0.0, 1.0], DOWN, 1.0),
        sphere(RED, DOWN, 2.5),
    ] {
        let again = pipeline.bake(mesh, &params, None).unwrap();
        assert_eq!(
            ran(&again),
            [("patches", false), ("volume", false), ("transfer", false)]
        );
        assert!(Arc::ptr_eq(&first.patches, &again.patches));
        assert!(Arc::ptr_eq(&first.volume, &again.volume));
    }

    // A new comb: the field and patches only.
    let combed = pipeline
        .bake(sphere(RED, [1.0, 0.0, 0.0], 1.0), &params, None)
        .unwrap();
    assert_eq!(
        ran(&combed),
        [("patches", true), ("volume", false), ("transfer", false)]
    );
    // Bald everywhere changes which faces get patches.
    let side_bald = || sphere(RED, [1.0, 0.0, 0.0], 0.0);
    let bald = pipeline.bake(side_bald(), &params, None).unwrap();
    assert_eq!(ran(&bald)[0], ("patches", true));
    assert!(bald.patches.patch.iter().all(|&p| p == lapped::NO_PATCH));

    // New hair: the volume and the transfer that reads it.
    let mut denser = params.clone();
    denser.hair.density = 500;
    let grown = pipeline.bake(side_bald(), &denser, None).unwrap();
    assert_eq!(
        ran(&grown),
        [("patches", false), ("volume", true), ("transfer", true)]
    );

    // A new fur depth: the transfer only (the volume is in tile units).
    let mut deeper = denser.clone();
    deeper.fur_depth = Some(0.25);
    let deep = pipeline.bake(side_bald(), &deeper, None).unwrap();
    assert_eq!(
        ran(&deep),
        [("patches", false), ("volume", false), ("transfer", true)]
    );
    assert_eq!(deep.transfer.as_ref().unwrap().depth_in_tiles, 0.5);

    // No transfer asked for: none in the asset and none in the report.
    let mut plain = deeper.clone();
    plain.transfer = None;
    let plain_asset = pipeline.bake(side_bald(), &plain, None).unwrap();
    assert!(plain_asset.transfer.is_none());
    assert_eq!(plain_asset.report.len(), 2);
}

/// The channels' shares of the linear color summed over the hair texels of the top quarter of the
/// layers, multiplied by `tint`: the color the hair tips show. Also the 95th percentile of the
/// shown red.
fn tips_shown(volume: &HairVolume, tint: [f32; 4]) -> ([f32; 3], f32) {
    let decode = crate::texture::color::srgb8_to_linear_table();
    let texels = volume.resolution * volume.resolution;
    let top = &volume.shells[(volume.layers * 3 / 4) * texels * 4..];
    let mut sum = [0.0f64; 3];
    let mut reds = Vec::new();
    for px in top.chunks_exact(4).filter(|px| px[3] > 0) {
        let shown: [f32; 3] = std::array::from_fn(|c| decode[px[c] as usize] * tint[c]);
        for c in 0..3 {
            sum[c] += f64::from(shown[c]);
        }
        reds.push(shown[0]);
    }
    let total: f64 = sum.iter().sum();
    reds.sort_by(f32::total_cmp);
    (sum.map(|c| (c / total) as f32), reds[reds.len() * 95 / 100])
}

#[test]
fn painted_colors_show_as_painted_and_the_coat_keeps_its_shading() {
    let mut params = small_params();
    params.hair.density = 3000;
    params.volume.resolution = 32;
    params.volume.layers = 16;
    let orange = [1.0, 0.45, 0.1, 1.0];
    let share = orange[..3].iter().sum::<f32>();
    let mut pipeline = Pipeline::new();
    let painted = pipeline.bake(sphere(orange, DOWN, 1.0), &params, None).unwrap();
    let (hue, bright) = tips_shown(&painted.volume, orange);
    // The tips show the paint's hue and, brightest, the paint itself (the coat's color would
    // give red 0.45 of it and a hue twice as red as green).
    for c in 0..3 {
        let expected = orange[c] / share;
        assert!(
            (hue[c] - expected).abs() < 0.1 * expected,
            "{hue:?} against {orange:?}"
        );
    }
    assert!(bright > 0.85, "brightest tips {bright}, painted 1.0");

    // Without paint the coat shows its own colors, and the patches (no vertex bald either way)
    // and the transfer (coverage only) are kept.
    let (positions, triangles) = uv_sphere(16, 8);
    let comb = vec![DOWN; positions.len()];
    let unpainted = FurMesh::new(MeshInput::new(&positions, &triangles).with_comb(&comb)).unwrap();
    let plain = pipeline.bake(Arc::new(unpainted), &params, None).unwrap();
    assert_eq!(
        ran(&plain),
        [("patches", false), ("volume", true), ("transfer", false)]
    );
    let tip = params.hair.tip_color;
    let (hue, bright) = tips_shown(&plain.volume, [1.0; 4]);
    let tip_share = tip.iter().sum::<f32>();
    for c in 0..3 {
        assert!(
            (hue[c] - tip[c] / tip_share).abs() < 0.1 * tip[c] / tip_share,
            "{hue:?}"
        );
    }
    assert!(
        (bright - tip[0]).abs() < 0.1 * tip[0],
        "brightest tips {bright}, tip {tip:?}"
    );
}

#[test]
fn a_bad_parameter_fails_before_any_stage_and_keeps_the_cache() {
    let mut pipeline = Pipeline::new();
    let params = small_params();
    pipeline.bake(sphere(RED, DOWN, 1.0), &params, None).unwrap();
    for (bad, field) in [
        (
            BakeParams {
                fur_depth: Some(f64::NAN),
                ..params.clone()
            },
            "fur_depth",
        ),
        (
            BakeParams {
                fur_depth: Some(0.0),
                ..params.clone()
            },
            "fur_depth",
        ),
        (
            {
                let mut p = params.clone();
                p.volume.layers = 0;
                p
            },
            "layers",
        ),
    ] {
        let calls = AtomicUsize::new(0);
        let count = |_: &str, _: f64| {
            calls.fetch_add(1, Ordering::Relaxed);
            true
        };
        let error = pipeline
            .bake(sphere(RED, DOWN, 1.0), &bad, Some(&count))
            .unwrap_err();
        assert!(error.to_string().contains(field), "{error}");
        assert_eq!(calls.load(Ordering::Relaxed), 0);
    }
    let again = pipeline.bake(sphere(RED, DOWN, 1.0), &params, None).unwrap();
    assert!(again.report.iter().all(|s| !s.ran));
}

#[test]
fn cancelling_keeps_finished_stages_and_drops_the_cancelled_one() {
    let mut pipeline = Pipeline::new();
    let params = small_params();
    let stages = std::sync::Mutex::new(Vec::new());
    let cancel_volume = |stage: &str, _: f64| {
        stages.lock().unwrap().push(stage.to_string());
        stage != "volume"
    };
    let error = pipeline
        .bake(sphere(RED, DOWN, 1.0), &params, Some(&cancel_volume))
        .unwrap_err();
    assert!(matches!(error, PeltError::Cancelled), "{error}");
    let heard = stages.into_inner().unwrap();
    assert!(heard.contains(&"patches".to_string()) && !heard.contains(&"transfer".to_string()));
    let resumed = pipeline.bake(sphere(RED, DOWN, 1.0), &params, None).unwrap();
    assert_eq!(
        ran(&resumed),
        [("patches", false), ("volume", true), ("transfer", true)]
    );
}

#[test]
fn the_planes_stage_runs_only_when_asked_and_when_its_inputs_change() {
    let mut pipeline = Pipeline::new();
    let mut params = small_params();
    params.transfer = None;
    let mesh = sphere(RED, DOWN, 1.0);
    let plain = pipeline.bake(mesh.clone(), &params, None).unwrap();
    assert!(plain.planes.is_none());
    assert_eq!(ran(&plain), [("patches", true), ("volume", true)]);

    params.planes = Some(PlaneParams {
        planes: 4,
        size: [16, 8],
    });
    let with = pipeline.bake(mesh.clone(), &params, None).unwrap();
    assert_eq!(
        ran(&with),
        [("patches", false), ("volume", false), ("planes", true)]
    );
    // The slices of the bake's own strands, as baked alone.
    let strands = crate::hair::grow_strands(&params.grown_hair(&mesh)).unwrap();
    let alone = bake_slices(&strands, |_| true, params.planes.as_ref().unwrap(), None).unwrap();
    assert_eq!(**with.planes.as_ref().unwrap(), alone);
    // Unchanged, reused; another count, baked again without the volume.
    let again = pipeline.bake(mesh.clone(), &params, None).unwrap();
    assert_eq!(ran(&again)[2], ("planes", false));
    params.planes.as_mut().unwrap().planes = 8;
    let more = pipeline.bake(mesh.clone(), &params, None).unwrap();
    assert_eq!(ran(&more)[1..], [("volume", false), ("planes", true)]);
    assert_eq!(more.planes.as_ref().unwrap().planes, 8);
    // A bad count is named before any stage runs.
    params.planes.as_mut().unwrap().planes = 0;
    match pipeline.bake(mesh, &params, None) {
        Err(PeltError::InvalidParameter { name, .. }) => assert_eq!(name, "planes"),
        other => panic!("{other:?}"),
    }
}
