//! The memory estimates that the budget checks before a stage allocates (`crates/pelt-core/src/memory.rs`) are
//! upper bounds of the heap the stage really takes: each stage runs here under a counting
//! allocator, and its measured peak must lie under the estimate, and not far under (an estimate
//! many times too high refuses bakes that would fit).
//!
//! One test function, so that no other test's allocations fall into a measurement.

use pelt::export::{
    ExportInput, GltfMode, GltfOptions, TextureFormats, TransferTextures, encode_glb, glb_peak_bytes,
    texture_set_peak_bytes, write_texture_set,
};
use pelt::hair::HairParams;
use pelt::heap::{TrackingAllocator, peak_heap};
use pelt::lapped::{PatchParams, build_patches};
use pelt::mesh::shapes::torus;
use pelt::prt::pack::{pack_f16, pack_u8};
use pelt::prt::peak::transfer_peak_bytes;
use pelt::prt::volume_input::VolumeInput;
use pelt::prt::{TransferParams, bake_transfer};
use pelt::volume::peak::grown_volume_peak_bytes;
use pelt::volume::{HairVolume, VolumeParams, bake_volume};
use pelt::{FurMesh, MeshInput, PeltError};

#[global_allocator]
static ALLOCATOR: TrackingAllocator = TrackingAllocator;

/// How far above the measured peak an estimate may lie.
const SLACK: f64 = 6.0;

fn measured<T>(what: &str, estimate: f64, work: impl FnOnce() -> T) -> T {
    let (out, peak) = peak_heap(work);
    let peak = peak.expect("the tracking allocator is installed") as f64;
    let ratio = estimate / peak;
    println!("{what}: estimate {estimate:.0} B, measured peak {peak:.0} B, ratio {ratio:.2}");
    assert!(
        estimate >= peak,
        "{what}: the estimate {estimate} B is under the measured peak {peak} B"
    );
    assert!(
        ratio <= SLACK,
        "{what}: the estimate {estimate} B is {ratio:.1}× the measured peak {peak} B"
    );
    out
}

#[test]
fn every_estimate_bounds_the_measured_peak() {
    TrackingAllocator::enable();
    let hair = HairParams::default();
    let params = VolumeParams {
        resolution: 64,
        layers: 16,
        fin_size: [128, 32],
        ..VolumeParams::default()
    };
    let volume = measured("bake_volume", grown_volume_peak_bytes(&params, &hair), || {
        bake_volume(&hair, &params, None).unwrap()
    });

    let transfer_params = TransferParams {
        order: 3,
        ..TransferParams::default()
    };
    let input = VolumeInput::new(&volume, 0.25);
    let transfer_volume = input.transfer_volume(&volume);
    let estimate = transfer_peak_bytes(volume.layers, volume.resolution, &transfer_params, false, false);
    let transfer = measured("bake_transfer", estimate, || {
        bake_transfer(&transfer_volume, &transfer_params, None).unwrap()
    });
    let (f16, u8) = (pack_f16(&transfer).unwrap(), pack_u8(&transfer).unwrap());

    #[cfg(feature = "render")]
    preview_uploads(&volume, &f16);

    let (positions, triangles) = torus(96, 48);
    let mesh = FurMesh::new(MeshInput::new(&positions, &triangles)).unwrap();
    let patches = PatchParams {
        tile_size: 0.5,
        ..PatchParams::default()
    };
    let patches = build_patches(&mesh, &patches).unwrap();
    let uvs = patches.uv.clone();
    let object = ExportInput {
        name: "Torus",
        mesh: &mesh,
        corner_uvs: &uvs,
        volume: &volume,
        transfer: Some(TransferTextures {
            order: 3,
            f16: &f16,
            u8: &u8,
        }),
        fur_depth: 0.1,
        shells: None,
        transform: Default::default(),
        skin: None,
        materials: None,
        animations: &[],
        guard_hairs: None,
    };
    let objects = [object];

    let folder = std::env::temp_dir().join(format!("pelt-memory-estimates-{}", std::process::id()));
    let formats = TextureFormats::default();
    let estimate = texture_set_peak_bytes(&objects[0], formats).unwrap();
    measured("write_texture_set", estimate, || {
        write_texture_set(&objects, &folder, formats).unwrap()
    });
    std::fs::remove_dir_all(&folder).unwrap();

    for mode in [GltfMode::Geometry, GltfMode::Engine] {
        let options = GltfOptions {
            mode,
            ..GltfOptions::default()
        };
        let estimate = glb_peak_bytes(&objects, &options).unwrap();
        measured(&format!("encode_glb {}", mode.name()), estimate, || {
            encode_glb(&objects, &[], &options).unwrap()
        });
    }

    // With guard hairs: lines (engine) or four ribbon vertices a point (geometry).
    let sparse = HairParams {
        density: 1000,
        guard_fraction: 0.1,
        ..HairParams::default()
    };
    let guard = pelt::guard::guard_hairs(&mesh, &patches, &sparse, 0.1, 1.0).unwrap();
    assert!(guard.spans.len() > 1000);
    let guarded = [ExportInput {
        guard_hairs: Some(&guard),
        ..objects[0]
    }];
    for mode in [GltfMode::Geometry, GltfMode::Engine] {
        let options = GltfOptions {
            mode,
            ..GltfOptions::default()
        };
        let estimate = glb_peak_bytes(&guarded, &options).unwrap();
        measured(
            &format!("encode_glb {} with guard hairs", mode.name()),
            estimate,
            || encode_glb(&guarded, &[], &options).unwrap(),
        );
    }

    // Above the limit, both exports refuse by name before writing or encoding anything.
    let (layers, resolution) = (64, 512);
    let voxels = layers * resolution * resolution;
    let big = HairVolume {
        resolution,
        layers,
        shells: vec![0; 4 * voxels],
        coverage: vec![0.0; voxels],
        tangents: vec![0; 4 * voxels],
        lod: Vec::new(),
        mips: Vec::new(),
        ..volume.clone()
    };
    let large = ExportInput {
        volume: &big,
        transfer: None,
        ..objects[0]
    };
    pelt::memory::set_limit(Some(64 << 20)).unwrap();
    let refused = write_texture_set(&[large], &folder, formats).unwrap_err();
    assert!(
        matches!(&refused, PeltError::MemoryLimit { stage, .. } if stage == "write_texture_set"),
        "{refused}"
    );
    assert!(refused.to_string().contains("`resolution` (512)"), "{refused}");
    assert!(
        !folder.exists(),
        "a refused texture set left {}",
        folder.display()
    );
    for mode in [GltfMode::Geometry, GltfMode::Engine] {
        let options = GltfOptions {
            mode,
            ..GltfOptions::default()
        };
        let refused = encode_glb(&[large], &[], &options).unwrap_err().to_string();
        assert!(refused.contains("export_gltf"), "{refused}");
    }
    pelt::memory::set_limit(None).unwrap();
}

/// The preview's texture uploads: a one-triangle scene, so that its geometry is next to nothing,
/// after a first scene has built the device's pipelines.
#[cfg(feature = "render")]
fn preview_uploads(volume: &HairVolume, transfer: &pelt::prt::pack::PackedF16) {
    use pelt::render::{
        AdapterChoice, FurScene, Renderer, scene_upload_peak_bytes, transfer_upload_peak_bytes,
    };
    let renderer = Renderer::new(AdapterChoice::Cpu).expect("a CPU adapter (lavapipe)");
    let mesh = FurMesh::new(MeshInput::new(
        &[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        &[[0, 1, 2]],
    ))
    .unwrap();
    let uvs = [[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]];
    let depth = 0.1;
    let mut warm = FurScene::new(&renderer, &mesh, &uvs, volume, depth).unwrap();
    warm.set_transfer(&renderer, transfer).unwrap();
    drop(warm);
    let mut scene = measured(
        "preview upload",
        scene_upload_peak_bytes(volume, &renderer),
        || FurScene::new(&renderer, &mesh, &uvs, volume, depth).unwrap(),
    );
    let order = scene.transfer_order().unwrap_or(3);
    let estimate = transfer_upload_peak_bytes(volume.layers, volume.resolution, order);
    measured("preview transfer upload", estimate, || {
        scene.set_transfer(&renderer, transfer).unwrap()
    });
    pelt::memory::set_limit(Some(pelt::memory::MIN_LIMIT)).unwrap();
    let big = HairVolume {
        resolution: 4096,
        ..volume.clone()
    };
    let refused = FurScene::new(&renderer, &mesh, &uvs, &big, depth)
        .err()
        .map(|e| e.to_string());
    pelt::memory::set_limit(None).unwrap();
    let refused = refused.expect("a 4096² volume is refused under the smallest limit");
    assert!(refused.contains("preview upload"), "{refused}");
}
