//! Bench cases of the guard strands in the wgpu preview (hybrid-fur-volume-and-strands §3):
//! Suzanne subdivided as in `render.frame`, her volume baked without the overcoat drawn as
//! strands, and that overcoat placed over her.
//!
//! - `render.frame.hybrid.upload`: [`FurScene::set_guard_hairs`] of about 100k strands.
//! - `render.frame.hybrid*`: the 512² (and 1080p) frame with the add-on's default share of the
//!   overcoat as strands, against the same scene's shells alone (`.shells`), as a preview draws
//!   it (`ShellMethod::Auto`) and instanced; `.100k` with about 100k strands.
//! - `render.frame.hybrid.order.*`: each [`StrandOrder`] timed and its error against the sorted
//!   composite ([`StrandOrder::Sorted`]): relative MSE and mean ꟻLIP over the fur's pixels.
//! - `render.frame.hybrid.lod`: 4× as far, the strand LOD's frame and how much of the strands'
//!   coverage it keeps (their added opacity with the LOD over without, composited exactly).

use super::render::{FUR_DEPTH, SHELLS, camera, camera_turned, note_adapter, shells_drawn, suzanne_patched};
use super::stream::streamed;
use super::{BenchOptions, CaseResult, time_fallible};
use pelt_core::error::Result;
use pelt_core::guard::guard_hairs;
use pelt_core::hair::HairParams;
use pelt_core::reference::metrics::{LinearRgba, flip_map};
use pelt_core::volume::{VolumeParams, bake_volume};
use pelt_render::{
    AdapterChoice, Camera, FurScene, Lighting, LinearImage, RenderSettings, Renderer, ShellMethod,
    StrandOrder,
};

/// The add-on's default share of the overcoat drawn as strands.
const DEFAULT_SHARE: f64 = 0.1;
/// The near cases' camera distance, and the strand LOD case's: far enough that every strand is
/// under a pixel wide, near enough that the silhouette, where the strands add coverage over the
/// opaque skin, is long.
const NEAR: f64 = 5.0;
const LOD_DISTANCE: f64 = 40.0;
/// Views around the mesh over which the strand LOD's coverage is summed.
const LOD_VIEWS: u32 = 12;
/// Strands of the upload case (the figure: 100k on a 60k-triangle mesh).
const UPLOAD_STRANDS: f64 = 100_000.0;

/// Premultiplied pixels of a straight-alpha linear image.
fn premultiplied(image: &LinearImage) -> Vec<[f32; 4]> {
    image
        .pixels
        .chunks_exact(4)
        .map(|p| [p[0] * p[3], p[1] * p[3], p[2] * p[3], p[3]])
        .collect()
}

/// Relative MSE (premultiplied RGB) and mean ꟻLIP of `image` against `reference`, over the
/// pixels either covers.
fn image_error(image: &LinearImage, reference: &LinearImage) -> (f64, f64) {
    let (p, r) = (premultiplied(image), premultiplied(reference));
    let (w, h) = (image.width as usize, image.height as usize);
    let flip = flip_map(
        LinearRgba {
            width: w,
            height: h,
            pixels: &p,
        },
        LinearRgba {
            width: w,
            height: h,
            pixels: &r,
        },
    );
    let (mut diff, mut norm, mut flips, mut n) = (0.0, 0.0, 0.0, 0usize);
    for i in (0..p.len()).filter(|&i| p[i][3] > 0.0 || r[i][3] > 0.0) {
        for c in 0..3 {
            diff += f64::from(p[i][c] - r[i][c]).powi(2);
            norm += f64::from(r[i][c]).powi(2);
        }
        flips += f64::from(flip[i]);
        n += 1;
    }
    (diff / norm.max(1e-30), flips / n.max(1) as f64)
}

/// Sum of alpha over the image.
fn coverage(image: &LinearImage) -> f64 {
    image.pixels.chunks_exact(4).map(|p| f64::from(p[3])).sum()
}

pub(super) fn strand_cases(options: &BenchOptions) -> Result<Vec<CaseResult>> {
    let renderer = Renderer::new(AdapterChoice::PreferHardware)?;
    let adapter = note_adapter(&renderer);
    let (mesh, patches) = suzanne_patched(options)?;
    let hair = HairParams::default();
    let volume = bake_volume(
        &hair,
        &VolumeParams {
            layers: SHELLS + 1,
            trim: false,
            guard_hairs: true,
            guard_share: DEFAULT_SHARE,
            ..VolumeParams::default()
        },
        None,
    )?;
    let depth = f64::from(FUR_DEPTH);
    let all = guard_hairs(&mesh, &patches, &hair, depth, 1.0)?.spans.len();
    let many = guard_hairs(
        &mesh,
        &patches,
        &hair,
        depth,
        (UPLOAD_STRANDS / all as f64).min(1.0),
    )?;
    let strands = guard_hairs(&mesh, &patches, &hair, depth, DEFAULT_SHARE)?;
    let mut scene = FurScene::new(&renderer, &mesh, &patches.uv, &volume, FUR_DEPTH)?;
    let reps: usize = if options.quick { 5 } else { 15 };
    let mut results = Vec::new();

    let timing = time_fallible(reps.div_ceil(3), || scene.set_guard_hairs(&renderer, &many))?;
    results.push(CaseResult::timed(
        "render.frame.hybrid.upload",
        format!(
            "{} strands of {} points on {} triangles (set_guard_hairs: tied to their root frames, sent); {adapter}",
            many.spans.len(),
            hair.segments + 1,
            mesh.face_count()
        ),
        timing,
    ));

    let lighting = Lighting::default();
    let preview = RenderSettings {
        shell_method: ShellMethod::Auto,
        ..RenderSettings::default()
    };
    let instanced = RenderSettings {
        shell_method: ShellMethod::Instanced,
        ..preview
    };
    let frame = |scene: &FurScene, name: &str, camera: &Camera, settings: &RenderSettings, what: &str| {
        let timing = time_fallible(reps, || renderer.render(scene, camera, &lighting, settings))?;
        let method = shells_drawn(&renderer, settings.shell_method);
        Ok::<_, pelt_core::PeltError>(CaseResult::timed(
            name,
            format!(
                "{}x{}, Suzanne ({} triangles), {SHELLS} shells + fins, {method}, {what}; {adapter}",
                camera.width,
                camera.height,
                mesh.face_count()
            ),
            timing,
        ))
    };
    let versus = |baseline: &CaseResult, case: CaseResult| CaseResult {
        baseline: Some(baseline.name.clone()),
        speedup: Some(baseline.seconds / case.seconds),
        ..case
    };
    let near = camera(NEAR, 512, 512);
    let hd = camera(NEAR, 1920, 1080);
    let few = format!("{} guard strands", strands.spans.len());
    let lots = format!("{} guard strands", many.spans.len());
    let cases: [(&str, &Camera, &RenderSettings); 3] = [
        ("render.frame.hybrid", &near, &preview),
        ("render.frame.hybrid.instanced", &near, &instanced),
        ("render.frame.hybrid.1080p", &hd, &preview),
    ];
    scene.set_guard_hairs(&renderer, &strands)?;
    for (name, camera, settings) in cases {
        let off = RenderSettings {
            guard_hairs: false,
            ..*settings
        };
        let shells = frame(&scene, &format!("{name}.shells"), camera, &off, "shells alone")?;
        let hybrid = frame(&scene, name, camera, settings, &few)?;
        results.push(versus(&shells, hybrid));
        results.push(shells);
    }
    // The 1080p hybrid frame as a window shows it (drawn into a texture, no readback), with
    // each shell method.
    for (method, settings) in [("", &preview), (".instanced", &instanced)] {
        for (part, hairs) in [("", true), (".shells", false)] {
            let settings = RenderSettings {
                guard_hairs: hairs,
                ..*settings
            };
            let streamed = streamed(&renderer, &scene, &hd, &lighting, &settings, reps.div_ceil(3))?;
            let what = if hairs { few.as_str() } else { "shells alone" };
            let shells = shells_drawn(&renderer, settings.shell_method);
            results.push(CaseResult::timed(
                &format!("render.frame.hybrid.stream.1080p{method}{part}"),
                format!(
                    "1920x1080, Suzanne ({} triangles), {SHELLS} shells + fins, {shells}, {what}, {}; {adapter}",
                    mesh.face_count(),
                    streamed.split()
                ),
                streamed.timing(),
            ));
        }
    }
    scene.set_guard_hairs(&renderer, &many)?;
    let full = frame(&scene, "render.frame.hybrid.100k", &near, &preview, &lots)?;
    results.push(full);
    scene.set_guard_hairs(&renderer, &strands)?;

    // The orders against the sorted composite, on instanced shells (the marched shells have one
    // order only).
    let with = |order| RenderSettings {
        strand_order: order,
        ..instanced
    };
    let sorted = renderer.render_linear(&scene, &near, &lighting, &with(StrandOrder::Sorted))?;
    for (label, order) in [
        ("stochastic", StrandOrder::Stochastic),
        ("depth", StrandOrder::Depth),
        ("banded4", StrandOrder::Banded(4)),
        ("sorted", StrandOrder::Sorted),
        ("none", StrandOrder::Depth),
    ] {
        let settings = if label == "none" {
            RenderSettings {
                guard_hairs: false,
                ..with(order)
            }
        } else {
            with(order)
        };
        let image = renderer.render_linear(&scene, &near, &lighting, &settings)?;
        let (mse, flip) = image_error(&image, &sorted);
        let what = if label == "none" {
            "the shells alone (what leaving the strands out costs)".to_string()
        } else {
            format!("{few}, {order:?}")
        };
        let mut case = frame(
            &scene,
            &format!("render.frame.hybrid.order.{label}"),
            &near,
            &settings,
            &what,
        )?;
        case.error = Some(flip);
        case.error_metric = Some(format!(
            "mean FLIP over the fur against StrandOrder::Sorted (relative MSE {mse:.2e})"
        ));
        results.push(case);
    }

    // The strand LOD far away: the strands' added coverage with it over without, composited
    // exactly (instanced shells, sorted strands: the marched hull and a depth-writing order
    // both let a strand hide fur behind it). Only strands past the opaque skin's silhouette
    // add any, a few pixels' worth a view at this distance, so it is summed over views all
    // around: one view's figure swung by ±100% with which strands the LOD kept there.
    let exact = RenderSettings {
        strand_order: StrandOrder::Sorted,
        ..instanced
    };
    let no_lod = RenderSettings {
        strand_pixels: 0.0,
        ..exact
    };
    let hidden = RenderSettings {
        guard_hairs: false,
        ..exact
    };
    let (mut kept, mut all_drawn) = (0.0, 0.0);
    for view in 0..LOD_VIEWS {
        let turn = std::f64::consts::TAU * f64::from(view) / f64::from(LOD_VIEWS);
        let around = camera_turned(LOD_DISTANCE, turn, 512, 512);
        let base = coverage(&renderer.render_linear(&scene, &around, &lighting, &hidden)?);
        kept += coverage(&renderer.render_linear(&scene, &around, &lighting, &exact)?) - base;
        all_drawn += coverage(&renderer.render_linear(&scene, &around, &lighting, &no_lod)?) - base;
    }
    let far = camera(LOD_DISTANCE, 512, 512);
    let mut lod = frame(
        &scene,
        "render.frame.hybrid.lod",
        &far,
        &preview,
        &format!("{few}, {}× as far", LOD_DISTANCE / NEAR),
    )?;
    lod.error = Some(kept / all_drawn.max(1e-30) - 1.0);
    lod.error_metric = Some(format!(
        "the strands' added coverage with the strand LOD over without, minus 1, summed over {LOD_VIEWS} views around \
         ({:.1} pixels a view without; instanced, sorted)",
        all_drawn / f64::from(LOD_VIEWS)
    ));
    results.push(lod);
    Ok(results)
}
