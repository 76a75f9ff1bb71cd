//! Bench cases of the wgpu fur renderer (`pelt-render`): frames of Suzanne subdivided to
//! about 62k triangles under lapped patches, 32 shells and fins, on the adapter [`Renderer`]
//! picks (hardware first). Uploads are not timed; every `render.frame*` frame is read back to
//! the CPU, while `render.stream*` draws frames back to back into a texture, as a window does.
//!
//! Where the time goes is read off the same frame with parts removed: `.skin` (skin only),
//! `.no_fins`, and `.tiny` (64², so fill costs next to nothing and what is left is vertex and
//! primitive work).

use std::sync::OnceLock;

use glam::DVec3;
use glam::dcamera::rh::proj::directx;
use glam::dcamera::rh::view::look_at_mat4;
use rayon::prelude::*;

use super::stream::streamed;
use super::{BenchOptions, CaseResult, time_fallible};
use pelt_core::error::Result;
use pelt_core::hair::HairParams;
use pelt_core::lapped::{PatchParams, Patches, build_patches};
use pelt_core::mesh::fin_quads;
use pelt_core::mesh::shapes::{subdivide, suzanne};
use pelt_core::mesh::{FurMesh, MeshInput};
use pelt_core::prt::pack::pack_f16;
use pelt_core::prt::sh::{self, ShRotation};
use pelt_core::prt::volume_input::VolumeInput;
use pelt_core::prt::{TransferParams, bake_transfer};
use pelt_core::scene::fin_cull::FinPlanes;
use pelt_core::threads::pool;
use pelt_core::volume::{HairVolume, VolumeParams, bake_volume};
use pelt_render::{
    AdapterChoice, Camera, FurScene, LightModel, Lighting, Prt, RenderSettings, Renderer, ShellMethod,
};

/// Name of the adapter the render cases ran on, for the report's `adapter` field.
static ADAPTER: OnceLock<String> = OnceLock::new();

/// Records `renderer`'s adapter as the one the render cases ran on, and returns its name.
pub(super) fn note_adapter(renderer: &Renderer) -> String {
    let adapter = renderer.adapter();
    let name = format!("{} ({}, {})", adapter.name, adapter.backend, adapter.device_type);
    let _ = ADAPTER.set(name.clone());
    name
}

/// The adapter used by the render cases, if any ran.
pub(super) fn adapter() -> Option<String> {
    ADAPTER.get().cloned()
}

/// Shells drawn (the volume has one layer more, the skin).
pub(super) const SHELLS: usize = 32;
/// Fur depth, object units (Suzanne is about 2.7 units wide).
pub(super) const FUR_DEPTH: f32 = 0.04;
/// World units per tile of the hair texture.
pub(super) const TILE: f64 = 0.25;

/// A camera `distance` units in front of Suzanne (she faces −y), a little above and to the side,
/// 40° vertical field of view, `width × height` pixels.
pub(super) fn camera(distance: f64, width: u32, height: u32) -> Camera {
    camera_turned(distance, 0.0, width, height)
}

/// [`camera`]'s view turned by `turn` radians about the vertical axis through the mesh.
pub(super) fn camera_turned(distance: f64, turn: f64, width: u32, height: u32) -> Camera {
    let eye = DVec3::new(0.35 * distance, -distance, 0.25 * distance);
    let (sin, cos) = turn.sin_cos();
    let eye = DVec3::new(cos * eye.x - sin * eye.y, sin * eye.x + cos * eye.y, eye.z);
    let aspect = f64::from(width) / f64::from(height);
    let projection = directx::perspective(40f64.to_radians(), aspect, 0.1, 10.0 * distance);
    Camera {
        view: look_at_mat4(eye, DVec3::ZERO, DVec3::Z).as_mat4().to_cols_array(),
        projection: projection.as_mat4().to_cols_array(),
        width,
        height,
    }
}

/// Rotates `light` (n² RGB coefficients) into the tile frame of every vertex (normal, dP/du,
/// dP/dv) with the crate's f64 SH rotation, as a CPU version of the PRT rotation pass would.
fn rotate_on_cpu(frames: &[[[f64; 3]; 3]], light: &[[f64; 3]]) -> Result<Vec<[f64; 3]>> {
    let order = sh::order_of_len(light.len())?;
    let channels: Vec<Vec<f64>> = (0..3).map(|c| light.iter().map(|l| l[c]).collect()).collect();
    pool().install(|| {
        frames
            .par_iter()
            .map(|&[n, dpdu, _]| {
                let (n, dpdu) = (DVec3::from(n), DVec3::from(dpdu));
                let x = dpdu - n * n.dot(dpdu);
                let x = x / x.length().max(1e-30);
                let rotation = ShRotation::new(order, [x, n.cross(x), n].map(|v| v.to_array()))?;
                let rotated = channels
                    .iter()
                    .map(|c| rotation.apply(c))
                    .collect::<Result<Vec<_>>>()?;
                Ok((0..light.len())
                    .map(|k| [rotated[0][k], rotated[1][k], rotated[2][k]])
                    .collect::<Vec<_>>())
            })
            .collect::<Result<Vec<Vec<_>>>>()
            .map(|rows| rows.concat())
    })
}

/// Suzanne subdivided three times (61,952 triangles; twice in `--quick`) under lapped patches of
/// `TILE`: the render cases' mesh.
pub(super) fn suzanne_patched(options: &BenchOptions) -> Result<(FurMesh, Patches)> {
    let levels = if options.quick { 2 } else { 3 };
    let mesh = FurMesh::new(subdivide(&suzanne(), levels).input())?;
    let patches = build_patches(
        &mesh,
        &PatchParams {
            tile_size: TILE,
            ..PatchParams::default()
        },
    )?;
    Ok((mesh, patches))
}

/// How `renderer` draws shells asked for with `method`, for a case's description.
pub(super) fn shells_drawn(renderer: &Renderer, method: ShellMethod) -> &'static str {
    match renderer.shell_method(method) {
        ShellMethod::Marched => "shells marched per pixel",
        _ => "shells instanced",
    }
}

/// `render.frame`: one frame of Suzanne subdivided three times (61,952 triangles; twice in
/// `--quick`, 15,488) with lapped-patch UVs, 32 shells and fins, Kajiya–Kay, at 512² and
/// 1920 × 1080, drawn as a preview draws it (`ShellMethod::Auto`: shells marched per pixel) and
/// each drawing the coarsest geometric level within a pixel of the full mesh (`.full_mesh` draws
/// every triangle); the parts (`.skin`, `.no_fins`, `.tiny`); `.lod`, the same scene 4× as far with LOD on
/// (baseline: the near frame); each shell method forced (`.instanced*`, `.marched*`); PRT
/// (`.prt` and `.instanced.prt`, order 5, not in `--quick`) with the CPU rotation it avoids
/// (`render.prt.rotate.cpu`); `render.stream*`, frames drawn back to back into a texture as a
/// window draws them (`.skin`, `.no_fins` and `.tiny` to split the 1080p frame's time); and the
/// scene's upload and a color update
/// (`render.scene.upload`, `render.scene.update`) and a pose (`render.scene.deform`).
pub(super) fn render_frame(options: &BenchOptions) -> Result<Vec<CaseResult>> {
    let renderer = Renderer::new(AdapterChoice::PreferHardware)?;
    let name = note_adapter(&renderer);
    let levels = if options.quick { 2 } else { 3 };
    let (mesh, patches) = suzanne_patched(options)?;
    let volume = bake_volume(
        &HairParams::default(),
        &VolumeParams {
            layers: SHELLS + 1,
            trim: false,
            ..VolumeParams::default()
        },
        None,
    )?;
    let mut scene = FurScene::new(&renderer, &mesh, &patches.uv, &volume, FUR_DEPTH)?;
    let reps = if options.quick { 5 } else { 15 };
    let upload_cases = scene_upload(&renderer, &mesh, &patches.uv, &volume, reps / 3)?;
    let cull_case = fin_cull(&mesh, reps)?;
    // The frame as the renderer draws it for a preview (`ShellMethod::Auto`: shells marched
    // per pixel); `.instanced` and `.marched` force one method.
    let settings = RenderSettings {
        shell_method: ShellMethod::Auto,
        ..RenderSettings::default()
    };
    let instanced = RenderSettings {
        shell_method: ShellMethod::Instanced,
        ..settings
    };
    let marched = RenderSettings {
        shell_method: ShellMethod::Marched,
        ..settings
    };
    let lighting = Lighting::default();
    let what = format!(
        "Suzanne subdivided {levels}× ({} triangles, {} GPU vertices, {} fins), {SHELLS} shells + fins",
        mesh.face_count(),
        scene.surface_vertex_count(),
        scene.fin_count(),
    );
    let mut results = Vec::new();
    let frame = |scene: &FurScene,
                 case: &str,
                 camera: &Camera,
                 settings: &RenderSettings,
                 lighting: &Lighting,
                 note: &str| {
        let timing = time_fallible(reps, || renderer.render(scene, camera, lighting, settings))?;
        let info = renderer.frame_info(scene, camera, settings)?;
        let method = shells_drawn(&renderer, settings.shell_method);
        let auto = if settings.shell_method == ShellMethod::Auto {
            " (auto)"
        } else {
            ""
        };
        // Which geometric level the frame drew (`RenderSettings::mesh_error`).
        let drawn = format!(
            ", {} triangles drawn (mesh level {})",
            info.triangles, info.mesh_level
        );
        let size = format!(
            "{}x{}, {what}{note}, {method}{auto}{drawn}; {name}",
            camera.width, camera.height
        );
        Ok::<_, pelt_core::PeltError>(CaseResult::timed(case, size, timing))
    };
    // The same frames drawn back to back into a texture, as a window shows them.
    let streamed_case = |scene: &FurScene,
                         case: &str,
                         camera: &Camera,
                         settings: &RenderSettings,
                         lighting: &Lighting,
                         note: &str| {
        let streamed = streamed(&renderer, scene, camera, lighting, settings, reps.div_ceil(3))?;
        let method = shells_drawn(&renderer, settings.shell_method);
        let size = format!(
            "{}x{}, {what}{note}, {method}, {}; {name}",
            camera.width,
            camera.height,
            streamed.split()
        );
        Ok::<_, pelt_core::PeltError>(CaseResult::timed(case, size, streamed.timing()))
    };
    let near = camera(5.0, 512, 512);
    let hd = camera(5.0, 1920, 1080);
    let versus = |baseline: &CaseResult, case: CaseResult| CaseResult {
        baseline: Some(baseline.name.clone()),
        speedup: Some(baseline.seconds / case.seconds),
        ..case
    };
    let no_fins = |s: &RenderSettings| RenderSettings { fins: false, ..*s };
    let kk = ", Kajiya-Kay";
    let slow = frame(&scene, "render.frame.instanced", &near, &instanced, &lighting, kk)?;
    let base = versus(
        &slow,
        frame(&scene, "render.frame", &near, &settings, &lighting, kk)?,
    );
    results.extend(upload_cases);
    results.push(cull_case);
    results.push(base.clone());
    results.push(frame(
        &scene,
        "render.frame.1080p",
        &hd,
        &settings,
        &lighting,
        kk,
    )?);
    // The light turning a little every other frame, as a character posed every frame does: the
    // body's shadow map is drawn again each time (`render.frame` draws it once and keeps it).
    let turned = Lighting {
        direction: [
            lighting.direction[0] + 0.05,
            lighting.direction[1],
            lighting.direction[2],
        ],
        ..lighting.clone()
    };
    let mut turn = false;
    let timing = time_fallible(reps, || {
        turn = !turn;
        let light = if turn { &turned } else { &lighting };
        renderer.render(&scene, &near, light, &settings)
    })?;
    let relit = format!(
        "{}x{}, {what}{kk}, the light turning every frame (the body's shadow map drawn each \
         time); {name}",
        near.width, near.height
    );
    results.push(versus(
        &base,
        CaseResult::timed("render.frame.relit", relit, timing),
    ));
    let skin = RenderSettings {
        shell_count: Some(0),
        ..no_fins(&settings)
    };
    results.push(frame(
        &scene,
        "render.frame.skin",
        &near,
        &skin,
        &lighting,
        ", skin only",
    )?);
    results.push(frame(
        &scene,
        "render.frame.no_fins",
        &near,
        &no_fins(&settings),
        &lighting,
        ", fins off",
    )?);
    let full_mesh = RenderSettings {
        mesh_error: 0.0,
        ..settings
    };
    results.push(frame(
        &scene,
        "render.frame.full_mesh",
        &near,
        &full_mesh,
        &lighting,
        ", every triangle (mesh_error 0)",
    )?);
    results.push(frame(
        &scene,
        "render.frame.tiny",
        &camera(5.0, 64, 64),
        &settings,
        &lighting,
        ", 64² (vertex-bound)",
    )?);
    let lod = RenderSettings {
        lod: true,
        min_shells: 1,
        max_shells: SHELLS as u32,
        ..settings
    };
    let far = camera(20.0, 512, 512);
    let info = renderer.frame_info(&scene, &far, &lod)?;
    let far_case = frame(
        &scene,
        "render.frame.lod",
        &far,
        &lod,
        &lighting,
        &format!(
            ", 4× as far with LOD: {} shells (level {}, blend {:.2}) for {:.1} px of fur",
            info.shells,
            info.level,
            info.blend,
            info.fur_pixels.unwrap_or(0.0)
        ),
    )?;
    results.push(versus(&base, far_case));
    results.push(slow);
    results.push(frame(
        &scene,
        "render.frame.instanced.1080p",
        &hd,
        &instanced,
        &lighting,
        kk,
    )?);
    results.push(frame(
        &scene,
        "render.frame.instanced.no_fins",
        &near,
        &no_fins(&instanced),
        &lighting,
        ", fins off",
    )?);
    results.push(frame(
        &scene,
        "render.frame.marched",
        &near,
        &marched,
        &lighting,
        kk,
    )?);
    results.push(frame(
        &scene,
        "render.frame.marched.1080p",
        &hd,
        &marched,
        &lighting,
        kk,
    )?);
    let viewport = camera(5.0, 960, 540);
    let tiny = camera(5.0, 64, 64);
    for (case, camera, settings, note) in [
        ("render.stream.540p", &viewport, &settings, kk),
        ("render.stream.1080p", &hd, &settings, kk),
        ("render.stream.1080p.instanced", &hd, &instanced, kk),
        ("render.stream.1080p.skin", &hd, &skin, ", skin only"),
        (
            "render.stream.1080p.no_fins",
            &hd,
            &no_fins(&settings),
            ", fins off",
        ),
        (
            "render.stream.tiny",
            &tiny,
            &settings,
            ", 64² (what a frame costs besides its pixels)",
        ),
    ] {
        results.push(streamed_case(&scene, case, camera, settings, &lighting, note)?);
    }
    if !options.quick {
        let order = 5;
        let input = VolumeInput::new(&volume, f64::from(FUR_DEPTH) / TILE);
        let transfer = bake_transfer(
            &input.transfer_volume(&volume),
            &TransferParams {
                order,
                ..TransferParams::default()
            },
            None,
        )?;
        scene.set_transfer(&renderer, &pack_f16(&transfer)?)?;
        let prt = Lighting {
            model: LightModel::Prt(Prt::default()),
            ..lighting
        };
        let prt_instanced = frame(
            &scene,
            "render.frame.instanced.prt",
            &near,
            &instanced,
            &prt,
            ", PRT order 5",
        )?;
        let prt_case = frame(
            &scene,
            "render.frame.prt",
            &near,
            &settings,
            &prt,
            ", PRT order 5",
        )?;
        let frames: Vec<[[f64; 3]; 3]> = (0..scene.surface_vertex_count())
            .map(|i| {
                let a = i as f64 * 0.618;
                let n = [a.cos() * 0.6, a.sin() * 0.6, 0.8];
                [n, [-a.sin(), a.cos(), 0.0], [0.0; 3]]
            })
            .collect();
        let light: Vec<[f64; 3]> = (0..sh::coeff_count(order))
            .map(|k| [1.0 / (1.0 + k as f64); 3])
            .collect();
        let timing = time_fallible(reps, || rotate_on_cpu(&frames, &light))?;
        for (case, settings) in [
            ("render.stream.1080p.prt", &settings),
            ("render.stream.1080p.prt.instanced", &instanced),
        ] {
            results.push(streamed_case(&scene, case, &hd, settings, &prt, ", PRT order 5")?);
        }
        results.push(versus(&prt_instanced, prt_case));
        results.push(prt_instanced);
        results.push(CaseResult::timed(
            "render.prt.rotate.cpu",
            format!(
                "{} vertices, order {order}, RGB: the per-frame rotation in f64 on the CPU that the compute pass replaces (plus a {} MB upload)",
                frames.len(),
                frames.len() * sh::coeff_count(order) * 16 / 1_000_000
            ),
            timing,
        ));
    }
    Ok(results)
}

/// `render.scene.upload`: a whole [`FurScene::new`] (split at seams, geometric levels with their
/// fins and vertex hosts, buffers and textures sent); `render.scene.update`: one
/// [`FurScene::update_attributes`] of new colors, with the check of which levels still hold them;
/// `render.scene.deform`: one [`FurScene::deform`] (the skin's posed vertices rebuilt and sent,
/// normals from the posed triangles; the fins' planes wait for a frame that draws them; `.normals` with the normals given, as the add-on passes
/// Blender's), two twists in turn.
fn scene_upload(
    renderer: &Renderer,
    mesh: &FurMesh,
    uvs: &[[[f32; 2]; 3]],
    volume: &HairVolume,
    reps: usize,
) -> Result<Vec<CaseResult>> {
    let timing = time_fallible(reps, || FurScene::new(renderer, mesh, uvs, volume, FUR_DEPTH))?;
    let mut scene = FurScene::new(renderer, mesh, uvs, volume, FUR_DEPTH)?;
    let size = format!(
        "{} triangles, geometric levels of {:?} triangles, {} layers of {}²",
        mesh.face_count(),
        scene.level_triangles(),
        volume.layers,
        volume.resolution
    );
    let upload = CaseResult::timed("render.scene.upload", size, timing);
    // Two smooth color ramps in turn, so that every update changes the colors.
    let ramps: [Vec<[f32; 4]>; 2] = [0.5, -0.5].map(|slope| {
        mesh.positions()
            .iter()
            .map(|p| [0.5 + slope * 0.2 * p[0], 0.5, 0.5, 1.0])
            .collect()
    });
    let mut turn = 0;
    let timing = time_fallible(reps.max(3) * 3, || {
        turn ^= 1;
        scene.update_attributes(Some(&ramps[turn]), None)
    })?;
    let update = CaseResult::timed(
        "render.scene.update",
        format!(
            "{} vertices' colors, {} of {} geometric levels still drawable",
            mesh.vertex_count(),
            scene.drawable_level_count(),
            scene.level_triangles().len()
        ),
        timing,
    );
    let twists: [Vec<[f32; 3]>; 2] = [0.4f32, -0.4].map(|rate| {
        mesh.positions()
            .iter()
            .map(|&[x, y, z]| {
                let (sin, cos) = (rate * y).sin_cos();
                [cos * x + sin * z, y, cos * z - sin * x]
            })
            .collect()
    });
    // The add-on's pose: Blender's own normals come with the positions.
    let twisted_normals: [Vec<[f32; 3]>; 2] = std::array::from_fn(|k| {
        FurMesh::new(MeshInput::new(&twists[k], mesh.triangles()))
            .map(|posed| posed.normals().to_vec())
            .unwrap_or_default()
    });
    let posed = format!(
        "{} vertices posed ({} GPU vertices; the planes of {} fin quads left to the frame)",
        mesh.vertex_count(),
        scene.surface_vertex_count(),
        scene.uploaded_fin_count()
    );
    let timing = time_fallible(reps.max(3) * 3, || {
        turn ^= 1;
        scene.deform(&twists[turn], None)
    })?;
    let deform = CaseResult::timed(
        "render.scene.deform",
        format!("{posed}, normals from the posed triangles"),
        timing,
    );
    let timing = time_fallible(reps.max(3) * 3, || {
        turn ^= 1;
        scene.deform(&twists[turn], Some(&twisted_normals[turn]))
    })?;
    let deform_given = CaseResult::timed(
        "render.scene.deform.normals",
        format!("{posed}, normals given (as Blender's)"),
        timing,
    );
    // Specks one vertex across, a different set each time: the coarse levels cannot hold them.
    let specks: [Vec<[f32; 4]>; 2] = [0, 48].map(|offset| {
        (0..mesh.vertex_count())
            .map(|v| {
                if (v + offset) % 97 == 0 {
                    [1.0, 0.1, 0.1, 1.0]
                } else {
                    [1.0; 4]
                }
            })
            .collect()
    });
    let timing = time_fallible(reps.max(3), || {
        turn ^= 1;
        scene.update_attributes(Some(&specks[turn]), None)?;
        scene.remake_levels(renderer)
    })?;
    let remake = CaseResult::timed(
        "render.scene.remake",
        format!(
            "{} vertices' colors with red specks the coarse levels cannot hold, then the levels made \
             anew under them (FurScene::remake_levels): levels of {:?} triangles",
            mesh.vertex_count(),
            scene.level_triangles()
        ),
        timing,
    );
    Ok(vec![upload, update, deform, deform_given, remake])
}

/// `render.fins.cull`: the fins a frame draws, collected on the CPU farthest first
/// ([`FinPlanes::visible_indices`], every frame that draws fins), over the full mesh's fins.
fn fin_cull(mesh: &FurMesh, reps: usize) -> Result<CaseResult> {
    let quads = fin_quads(mesh, 1.0);
    let planes = FinPlanes::new(
        quads.iter().map(|q| q.center).collect(),
        quads.iter().map(|q| q.normal).collect(),
    );
    let fins = 0..quads.len() as u32;
    let eye = [1.75, -5.0, 1.25, 1.0];
    let cull = || pool().install(|| planes.visible_indices(eye, fins.clone()));
    let kept = cull().len() / 6;
    let timing = time_fallible(reps.max(3) * 3, || Ok::<_, pelt_core::PeltError>(cull()))?;
    Ok(CaseResult::timed(
        "render.fins.cull",
        format!(
            "{} fins of {} triangles, {kept} left visible from the bench's camera, farthest first ({} threads)",
            quads.len(),
            mesh.face_count(),
            pool().current_num_threads()
        ),
        timing,
    ))
}
