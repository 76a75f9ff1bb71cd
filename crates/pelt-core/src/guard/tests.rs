use std::sync::Arc;

use super::*;
use crate::hair::grow_strands;
use crate::mesh::shapes::uv_sphere;
use crate::pipeline::{BakeParams, Pipeline};
use crate::volume::{HairVolume, VolumeParams, bake_strands, bake_volume};
use crate::{FurMesh, MeshInput};

const TILE: f64 = 0.5;
const DEPTH: f64 = 0.15;

fn hair(guard_fraction: f64) -> HairParams {
    HairParams {
        density: 400,
        guard_fraction,
        ..HairParams::default()
    }
}

/// A unit sphere baked with guard hairs; lengths 0 below z = −0.5 (a bald cap).
fn sphere(hair: &HairParams) -> (Arc<FurMesh>, crate::pipeline::FurAsset) {
    let (positions, triangles) = uv_sphere(32, 16);
    let length: Vec<f32> = positions
        .iter()
        .map(|p| if p[2] < -0.5 { 0.0 } else { 1.0 })
        .collect();
    let mesh = Arc::new(FurMesh::new(MeshInput::new(&positions, &triangles).with_length(&length)).unwrap());
    let mut params = BakeParams::default();
    params.patches.tile_size = TILE;
    params.hair = hair.clone();
    params.volume.resolution = 32;
    params.volume.layers = 8;
    params.volume.guard_hairs = true;
    params.fur_depth = Some(DEPTH);
    params.transfer = None;
    let asset = Pipeline::new().bake(mesh.clone(), &params, None).unwrap();
    (mesh, asset)
}

/// The coat of `hair` baked whole, and with a `share` of its guard hairs left to strands (no
/// trim, so the two have the same layers); the parameters of both.
fn whole_and_split(hair: &HairParams, share: f64) -> (VolumeParams, HairVolume, HairVolume) {
    let params = VolumeParams {
        resolution: 32,
        layers: 8,
        trim: false,
        ..VolumeParams::default()
    };
    let all = bake_volume(hair, &params, None).unwrap();
    let split = VolumeParams {
        guard_hairs: true,
        guard_share: share,
        ..params.clone()
    };
    let split = bake_volume(hair, &split, None).unwrap();
    (params, all, split)
}

/// The strands and coverage of `shells` and `strands` together are those of `all`: coverage is
/// a sum over strands.
fn assert_adds_up(all: &HairVolume, shells: &HairVolume, strands: &HairVolume) {
    assert_eq!(shells.stats.strands + strands.stats.strands, all.stats.strands);
    let worst = (0..all.coverage.len())
        .map(|i| (all.coverage[i] - shells.coverage[i] - strands.coverage[i]).abs())
        .fold(0.0f32, f32::max);
    assert!(worst < 1e-4, "coverage differs by {worst}");
}

#[test]
fn the_undercoat_volume_and_the_guard_hairs_share_out_the_coat_without_loss() {
    // Coverage is a sum over strands: the undercoat's and the overcoat's add up to the coat's.
    let hair = hair(0.2);
    let (params, all, under) = whole_and_split(&hair, 1.0);
    let overcoat: Vec<_> = grow_strands(&hair)
        .unwrap()
        .into_iter()
        .filter(|s| s.coat == Coat::Overcoat)
        .collect();
    let over = bake_strands(&overcoat, &params, None).unwrap();
    assert!(over.stats.strands > 0 && under.stats.strands > over.stats.strands);
    assert_adds_up(&all, &under, &over);
}

#[test]
fn guard_hairs_stand_on_the_furred_surface_as_many_as_the_overcoat_gives() {
    let hair = hair(0.2);
    let (mesh, asset) = sphere(&hair);
    let guard = asset.guard_hairs.as_ref().expect("a bake with guard hairs");
    let overcoat = grow_strands(&hair)
        .unwrap()
        .iter()
        .filter(|s| s.coat == Coat::Overcoat)
        .count();
    // Roots land once per tile repeat: the overcoat per tile times the furred area in tiles
    // (the cap below z = -0.5 is bald; its border triangles are half furred).
    let furred_area = 2.0 * std::f64::consts::PI * 1.5;
    let expected = overcoat as f64 * furred_area / (TILE * TILE);
    let ratio = guard.spans.len() as f64 / expected;
    assert!(
        (0.85..1.15).contains(&ratio),
        "{} guard hairs, expected about {expected:.0}",
        guard.spans.len()
    );
    assert_eq!(
        guard.points.len(),
        guard.spans.iter().map(|s| s.count as usize).sum::<usize>()
    );
    for span in &guard.spans {
        let points = &guard.points[span.first as usize..(span.first + span.count) as usize];
        let radius = |p: &[f32; 4]| (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
        let (root, tip) = (points[0], points[points.len() - 1]);
        // The faceted sphere's faces lie within 1 - cos(π/16) ≈ 0.019 of the unit sphere.
        assert!(
            (0.98..=1.0001).contains(&radius(&root)),
            "root at radius {}",
            radius(&root)
        );
        // The first bald ring stands at z = cos(11π/16) ≈ -0.556; the band above it is half furred.
        assert!(
            root[2] > -0.556,
            "a guard hair on the bald cap at z = {}",
            root[2]
        );
        assert!(radius(&tip) > radius(&root) && radius(&tip) < 1.0 + 1.5 * DEPTH as f32);
        assert!(
            points
                .iter()
                .all(|p| p.iter().all(|v| v.is_finite()) && p[3] > 0.0)
        );
        // The root's triangle and weights give its place back (what Blender attaches it by).
        let corners = mesh.triangles()[span.triangle as usize].map(|v| mesh.positions()[v as usize]);
        let w = span.weights;
        assert!(w.iter().all(|&x| x >= -1e-5) && (w.iter().sum::<f32>() - 1.0).abs() < 1e-5);
        for axis in 0..3 {
            let at: f32 = (0..3).map(|k| w[k] * corners[k][axis]).sum();
            assert!((at - root[axis]).abs() < 1e-5, "root {root:?} vs weights {w:?}");
        }
    }
    // The shells hold the undercoat alone.
    assert_eq!(
        asset.volume.stats.strands,
        grow_strands(&hair).unwrap().len() - overcoat
    );
    assert!(asset.report.iter().any(|r| r.stage == "guard_hairs" && r.ran));
}

#[test]
fn a_rebake_reuses_the_guard_hairs_until_what_they_read_changes() {
    let hair = hair(0.2);
    let (positions, triangles) = uv_sphere(16, 8);
    let mesh = Arc::new(FurMesh::new(MeshInput::new(&positions, &triangles)).unwrap());
    let mut params = BakeParams::default();
    params.patches.tile_size = TILE;
    params.hair = hair;
    params.volume.resolution = 16;
    params.volume.layers = 4;
    params.volume.guard_hairs = true;
    params.transfer = None;
    let mut pipeline = Pipeline::new();
    let first = pipeline.bake(mesh.clone(), &params, None).unwrap();
    let ran = |asset: &crate::pipeline::FurAsset| {
        asset
            .report
            .iter()
            .find(|r| r.stage == "guard_hairs")
            .map(|r| r.ran)
    };
    assert_eq!(ran(&first), Some(true));
    let again = pipeline.bake(mesh.clone(), &params, None).unwrap();
    assert_eq!(ran(&again), Some(false));
    assert!(Arc::ptr_eq(
        first.guard_hairs.as_ref().unwrap(),
        again.guard_hairs.as_ref().unwrap()
    ));
    params.fur_depth = Some(0.3);
    let deeper = pipeline.bake(mesh.clone(), &params, None).unwrap();
    assert_eq!(ran(&deeper), Some(true));
    params.volume.guard_hairs = false;
    let without = pipeline.bake(mesh, &params, None).unwrap();
    assert!(without.guard_hairs.is_none() && ran(&without).is_none());
}

#[test]
fn bad_guard_hair_input_is_named_before_any_stage_runs() {
    let (positions, triangles) = uv_sphere(8, 4);
    let mesh = Arc::new(FurMesh::new(MeshInput::new(&positions, &triangles)).unwrap());
    let named = |hair: HairParams, depth: f64| {
        let params = BakeParams {
            hair,
            volume: VolumeParams {
                guard_hairs: true,
                ..VolumeParams::default()
            },
            fur_depth: Some(depth),
            transfer: None,
            ..BakeParams::default()
        };
        match Pipeline::new().bake(mesh.clone(), &params, None) {
            Err(PeltError::InvalidParameter { name, reason }) => format!("{name}: {reason}"),
            other => panic!("expected a named error, got {:?}", other.map(|a| a.report)),
        }
    };
    assert!(named(hair(0.0), 0.1).starts_with("guard_fraction: is 0"));
    let mut thin = hair(0.2);
    thin.overcoat.width = [0.0, 0.004];
    assert!(named(thin, 0.1).starts_with("overcoat.width"));
    let mut nan = hair(0.2);
    nan.overcoat.width = [f64::NAN, 0.004];
    assert!(named(nan, 0.1).starts_with("overcoat.width"));
}

#[test]
fn more_guard_hairs_than_the_limit_are_refused_before_they_are_placed() {
    let (positions, triangles) = uv_sphere(16, 8);
    let mesh = FurMesh::new(MeshInput::new(&positions, &triangles)).unwrap();
    let tile = 0.1;
    let patches = crate::lapped::build_patches(
        &mesh,
        &crate::lapped::PatchParams {
            tile_size: tile,
            ..Default::default()
        },
    )
    .unwrap();
    // About 1,200 tiles of 1,024 guard hairs each.
    let dense = HairParams {
        density: 1024,
        guard_fraction: 1.0,
        ..HairParams::default()
    };
    let error = guard_hairs(&mesh, &patches, &dense, 0.1, 1.0)
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("`guard_fraction`") && error.contains(&format!("at most {MAX_GUARD_STRANDS}")),
        "{error}"
    );
}

#[test]
fn guard_hairs_scale_with_the_mesh_from_1e_minus_20_to_1e20() {
    // Powers of two scale every product exactly: the strands must come out scaled bit for bit
    // (their radii once overflowed to inf at ×1e20, the squared lengths in f32).
    let (positions, triangles) = uv_sphere(12, 6);
    let hair = hair(0.3);
    let place = |scale: f32| {
        let scaled: Vec<[f32; 3]> = positions.iter().map(|p| p.map(|c| c * scale)).collect();
        let mesh = FurMesh::new(MeshInput::new(&scaled, &triangles)).unwrap();
        let params = crate::lapped::PatchParams {
            tile_size: 0.5 * f64::from(scale),
            ..Default::default()
        };
        let patches = crate::lapped::build_patches(&mesh, &params).unwrap();
        guard_hairs(&mesh, &patches, &hair, 0.2 * f64::from(scale), 1.0).unwrap()
    };
    let unit = place(1.0);
    assert!(!unit.spans.is_empty());
    for exponent in [-66, 66] {
        let scale = 2f32.powi(exponent);
        let scaled = place(scale);
        assert_eq!(scaled.spans, unit.spans);
        for (a, b) in unit.points.iter().zip(&scaled.points) {
            assert_eq!(a.map(|v| v * scale), *b, "at 2^{exponent}");
        }
    }
}

#[test]
fn a_share_of_the_guard_hairs_draws_that_share_and_leaves_the_rest_in_the_shells() {
    let hair = hair(0.3);
    let (params, all, mixed) = whole_and_split(&hair, 0.5);
    let grown = grow_strands(&hair).unwrap();
    let mask = drawn_as_strands(&grown, 0.5);
    let drawn: Vec<_> = grown
        .iter()
        .zip(&mask)
        .filter(|(_, d)| **d)
        .map(|(s, _)| s.clone())
        .collect();
    let overcoat = grown.iter().filter(|s| s.coat == Coat::Overcoat).count();
    assert_eq!(drawn.len(), (overcoat as f64 / 2.0).round() as usize);
    assert!(drawn.iter().all(|s| s.coat == Coat::Overcoat));
    // A smaller share draws a subset of a larger one's.
    let fewer = drawn_as_strands(&grown, 0.2);
    assert!(fewer.iter().zip(&mask).all(|(&f, &m)| !f || m));
    let strands = bake_strands(&drawn, &params, None).unwrap();
    assert_adds_up(&all, &mixed, &strands);
    // Over a mesh, half the share places about half the guard hairs.
    let (positions, triangles) = uv_sphere(16, 8);
    let mesh = FurMesh::new(MeshInput::new(&positions, &triangles)).unwrap();
    let patches = crate::lapped::build_patches(&mesh, &Default::default()).unwrap();
    let count = |share| {
        guard_hairs(&mesh, &patches, &hair, 0.1, share)
            .unwrap()
            .spans
            .len() as f64
    };
    let ratio = count(0.5) / count(1.0);
    assert!((0.45..0.55).contains(&ratio), "{ratio}");
    for bad in [0.0, -1.0, 1.5, f64::NAN] {
        let error = guard_hairs(&mesh, &patches, &hair, 0.1, bad)
            .unwrap_err()
            .to_string();
        assert!(error.contains("`guard_share`"), "{error}");
    }
}
