//! Bench cases of the wgpu fur renderer (feature `render`).

use std::sync::OnceLock;

use super::{BenchOptions, CaseResult, time_fallible};
use crate::error::Result;
use crate::hair::HairParams;
use crate::mesh::shapes::{torus, torus_uvs};
use crate::mesh::{FurMesh, MeshInput};
use crate::render::{AdapterChoice, Camera, FurScene, Lighting, RenderSettings, Renderer};
use crate::volume::{VolumeParams, bake_volume};

/// Name of the adapter the render cases ran on, for the report's `adapter` field.
static ADAPTER: OnceLock<String> = OnceLock::new();

/// The adapter used by the render cases, if any ran.
pub(super) fn adapter() -> Option<String> {
    ADAPTER.get().cloned()
}

fn column_major(rows: [[f32; 4]; 4]) -> [f32; 16] {
    std::array::from_fn(|i| rows[i % 4][i / 4])
}

/// A camera 3.4 units from the torus, 40° above its plane, 60° field of view.
fn camera(side: u32) -> Camera {
    let (s, c) = 40f32.to_radians().sin_cos();
    let (near, far, t) = (0.5f32, 10.0f32, 1.0 / 30f32.to_radians().tan());
    let d = 3.4f32;
    Camera {
        // Eye at (0, -d c, d s) looking at the origin, z up.
        view: column_major([
            [1.0, 0.0, 0.0, 0.0],
            [0.0, s, c, 0.0],
            [0.0, -c, s, -d],
            [0.0, 0.0, 0.0, 1.0],
        ]),
        projection: column_major([
            [t, 0.0, 0.0, 0.0],
            [0.0, t, 0.0, 0.0],
            [0.0, 0.0, far / (near - far), near * far / (near - far)],
            [0.0, 0.0, -1.0, 0.0],
        ]),
        width: side,
        height: side,
    }
}

/// `render.frame`: one 512² frame (skin, fins, 16 shells, Kajiya–Kay) of a 5,120-face torus with
/// the default hair volume, read back to the CPU; on the adapter `Renderer` picks (hardware
/// first). The upload is not timed. `render.frame.skin` times the same frame with the skin only.
pub(super) fn render_frame(options: &BenchOptions) -> Result<Vec<CaseResult>> {
    let renderer = Renderer::new(AdapterChoice::PreferHardware)?;
    let adapter = renderer.adapter();
    let name = format!("{} ({}, {})", adapter.name, adapter.backend, adapter.device_type);
    let _ = ADAPTER.set(name.clone());
    let (around, across) = (64, 40);
    let (positions, triangles) = torus(around, across);
    let mesh = FurMesh::new(MeshInput::new(&positions, &triangles))?;
    let uvs = torus_uvs(around, across, [6.0, 2.0]);
    // 17 layers: the skin and 16 shells.
    let params = VolumeParams {
        layers: 17,
        trim: false,
        ..VolumeParams::default()
    };
    let volume = bake_volume(&HairParams::default(), &params, None)?;
    let scene = FurScene::new(&renderer, &mesh, &uvs, &volume)?;
    let side = 512;
    let settings = RenderSettings {
        fur_depth: 0.06,
        ..RenderSettings::default()
    };
    let (camera, lighting) = (camera(side), Lighting::default());
    let reps = if options.quick { 5 } else { 21 };
    let timing = time_fallible(reps, || renderer.render(&scene, &camera, &lighting, &settings))?;
    let size = format!(
        "{side}x{side}, {} faces, {} fins, {} shells, Kajiya-Kay, readback incl.; {name}",
        triangles.len(),
        scene.fin_count(),
        scene.layers() - 1,
    );
    // The same frame with the skin only: what the fur itself costs.
    let skin = RenderSettings {
        shell_count: Some(0),
        fins: false,
        ..settings
    };
    let skin_timing = time_fallible(reps, || renderer.render(&scene, &camera, &lighting, &skin))?;
    let skin_size = format!("{side}x{side}, {} faces, skin only; {name}", triangles.len());
    Ok(vec![
        CaseResult::timed("render.frame", size, timing),
        CaseResult::timed("render.frame.skin", skin_size, skin_timing),
    ])
}
