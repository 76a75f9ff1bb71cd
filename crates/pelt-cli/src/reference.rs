//! `pelt reference SOURCE --out IMAGE.exr`: renders a ground-truth image with the reference
//! renderer (`pelt_core::reference`) of a baked folder (from `pelt bake`) or of a canonical scene
//! (`sphere.short.side`, …), as linear OpenEXR (premultiplied RGBA) and an sRGB PNG beside it.
//! `--mode volume` renders the bake's density volume instead of its strands (the hybrid paper's
//! method). `--environment IMAGE` lights it by a light probe instead. Both files appear only when the render finished (written under a temporary name,
//! then renamed); Ctrl+C or an error leaves nothing.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use clap::{Args, ValueEnum};
use pelt_core::camera::Camera;
use pelt_core::export::{ExrOptions, PngOptions, save_exr, save_png};
use pelt_core::hair::{Strand, grow_strands};
use pelt_core::lapped::Patches;
use pelt_core::mesh::FurMesh;
use pelt_core::prt::sh::project_equirect;
use pelt_core::reference::scenes::{FurLength, LightSetup, Shape, canonical_scene, framing};
use pelt_core::reference::{
    FurGeometry, ReferenceImage, ReferenceLight, ReferenceScene, ReferenceSettings, VolumeScene,
    render_reference, render_volume_reference,
};
use pelt_core::texture::{ImageRef, read_light_probe};
use pelt_core::volume::{HairVolume, bake_strands};

use crate::bake::{bake_object, load_record, prepare};

#[derive(Args)]
pub struct ReferenceArgs {
    /// A baked folder (its bake.json), or a canonical scene SHAPE.LENGTH.LIGHT: shape patch,
    /// sphere, suzanne or torus; length short or long; light eye, side, back, top or
    /// environment.
    pub source: String,
    /// The OpenEXR file to write; the PNG goes beside it with the same stem.
    #[arg(long, value_name = "FILE")]
    pub out: PathBuf,
    /// Image side in pixels (square).
    #[arg(long, default_value_t = 512)]
    pub size: u32,
    /// Fewest samples per pixel.
    #[arg(long, default_value_t = 16)]
    pub samples: u32,
    /// Relative standard error of the mean radiance to reach.
    #[arg(long, default_value_t = 0.01)]
    pub target_error: f64,
    /// The object of a baked folder to render (default: the first).
    #[arg(long)]
    pub object: Option<String>,
    /// What to trace: the strands, or the density volume baked from them.
    #[arg(long, value_enum, default_value_t = Mode::Strands)]
    pub mode: Mode,
    /// Light the fur by this latitude–longitude image (Radiance HDR, OpenEXR, or sRGB PNG)
    /// instead of the source's lights: linear radiance, object space, row 0 straight up (+Z),
    /// the left edge facing +X and azimuth turning toward +Y.
    #[arg(long, value_name = "IMAGE")]
    pub environment: Option<PathBuf>,
    /// Spherical-harmonic order the environment is projected to, [1, 8].
    #[arg(long, default_value_t = 8)]
    pub environment_order: usize,
}

/// The reference's two modes.
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Mode {
    /// The tile's strands placed over the mesh.
    Strands,
    /// The baked hair volume ray marched through the triangles' prisms.
    Volume,
}

/// What both modes are built from.
struct Fur {
    mesh: Arc<FurMesh>,
    patches: Arc<Patches>,
    strands: Vec<Strand>,
    volume: Arc<HairVolume>,
    fur_depth: f64,
}

impl Fur {
    fn render(
        &self,
        mode: Mode,
        camera: &Camera,
        lights: &[ReferenceLight],
        settings: &ReferenceSettings,
        progress: pelt_core::progress::ProgressCallback<'_>,
    ) -> pelt_core::Result<ReferenceImage> {
        match mode {
            Mode::Strands => {
                let geometry =
                    FurGeometry::from_bake(&self.mesh, &self.patches, &self.strands, self.fur_depth)?;
                let scene = ReferenceScene::new(geometry)?;
                eprintln!("reference: {} strands", scene.strand_count());
                render_reference(&scene, camera, lights, settings, Some(progress))
            }
            Mode::Volume => {
                let scene = VolumeScene::from_bake(
                    &self.mesh,
                    &self.patches,
                    &self.volume,
                    &self.strands,
                    self.fur_depth,
                )?;
                eprintln!("reference: the volume in {} prisms", scene.prism_count());
                render_volume_reference(&scene, camera, lights, settings, Some(progress))
            }
        }
    }
}

pub fn run(args: ReferenceArgs) -> Result<(), String> {
    let settings = ReferenceSettings {
        min_samples: args.samples,
        max_samples: args.samples.max(1024),
        target_error: args.target_error,
        ..ReferenceSettings::default()
    };
    settings.validate().map_err(|e| e.to_string())?;
    // Read before the bake, so a bad image costs nothing.
    let environment = args
        .environment
        .as_deref()
        .map(|path| environment(path, args.environment_order))
        .transpose()?;
    let (fur, camera, mut lights) = if Path::new(&args.source).is_dir() {
        baked_folder(&args)?
    } else {
        canonical(&args)?
    };
    if let Some(light) = environment {
        lights = vec![light];
    }
    let progress = |done: f64| {
        eprint!("\rreference: {:3.0}%", 100.0 * done);
        let _ = std::io::stderr().flush();
        true
    };
    let image = fur
        .render(args.mode, &camera, &lights, &settings, &progress)
        .map_err(|e| e.to_string())?;
    eprintln!(
        "\rreference: {} samples/pixel, mean radiance within {:.2}% (pixels {:.1}%), {:.1} s",
        image.samples,
        100.0 * image.relative_error,
        100.0 * image.pixel_error,
        image.seconds
    );
    let (w, h) = (image.width as usize, image.height as usize);
    let linear: Vec<f32> = image.pixels.iter().flatten().copied().collect();
    let png_path = args.out.with_extension("png");
    let exr_part = part(&args.out);
    let png_part = part(&png_path);
    let written = (|| {
        save_exr(
            &exr_part,
            &ImageRef::new(w, h, 4, &linear)?,
            &ExrOptions::default(),
        )?;
        let display = image.display_rgba8();
        let options = PngOptions {
            srgb: true,
            ..PngOptions::default()
        };
        save_png(&png_part, &ImageRef::new(w, h, 4, &display)?, &options)
    })();
    let renamed = written.map_err(|e| e.to_string()).and_then(|()| {
        std::fs::rename(&exr_part, &args.out).map_err(|e| format!("{}: {e}", args.out.display()))?;
        std::fs::rename(&png_part, &png_path).map_err(|e| format!("{}: {e}", png_path.display()))
    });
    if renamed.is_err() {
        let _ = std::fs::remove_file(&exr_part);
        let _ = std::fs::remove_file(&png_part);
    }
    renamed?;
    println!("pelt: wrote {} and {}", args.out.display(), png_path.display());
    Ok(())
}

/// The light probe at `path` projected onto SH of `order`.
fn environment(path: &Path, order: usize) -> Result<ReferenceLight, String> {
    let probe = read_light_probe(path).map_err(|e| e.to_string())?;
    let sh = project_equirect(order, probe.width, probe.height, &probe.rgb).map_err(|e| e.to_string())?;
    Ok(ReferenceLight::Environment {
        sh: sh.iter().map(|c| c.map(|v| v as f32)).collect(),
    })
}

/// `path` with `.part` added: where a file is written before it is renamed into place.
fn part(path: &Path) -> PathBuf {
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(".part");
    path.with_file_name(name)
}

type Prepared = (Fur, Camera, Vec<ReferenceLight>);

fn canonical(args: &ReferenceArgs) -> Result<Prepared, String> {
    let parts: Vec<&str> = args.source.split('.').collect();
    let find = |i: usize, names: &[&str]| {
        parts
            .get(i)
            .and_then(|p| names.iter().position(|n| n == p))
            .ok_or_else(|| {
                format!(
                    "{:?} is neither a folder nor a canonical scene SHAPE.LENGTH.LIGHT \
                 (shape: patch, sphere, suzanne, torus; length: short, long; \
                 light: eye, side, back, top, environment)",
                    args.source
                )
            })
    };
    let shape = Shape::ALL[find(0, &Shape::ALL.map(Shape::name))?];
    let length = FurLength::ALL[find(1, &FurLength::ALL.map(FurLength::name))?];
    let light = LightSetup::ALL[find(2, &LightSetup::ALL.map(LightSetup::name))?];
    if parts.len() != 3 {
        return Err(format!("{:?}: expected SHAPE.LENGTH.LIGHT", args.source));
    }
    let scene = canonical_scene(shape, length, light, args.size).map_err(|e| e.to_string())?;
    let strands = grow_strands(&scene.params.grown_hair(&scene.mesh)).map_err(|e| e.to_string())?;
    let patches =
        pelt_core::lapped::build_patches(&scene.mesh, &scene.params.patches).map_err(|e| e.to_string())?;
    let volume = bake_strands(&strands, &scene.params.volume, None).map_err(|e| e.to_string())?;
    let fur = Fur {
        mesh: scene.mesh.clone(),
        patches: Arc::new(patches),
        strands,
        volume: Arc::new(volume),
        fur_depth: scene.params.fur_depth(),
    };
    Ok((fur, scene.camera, scene.lights))
}

/// A baked folder: the object baked again from its record (the bake is deterministic), framed
/// from the front and lit by a sun of strength π from the upper right.
fn baked_folder(args: &ReferenceArgs) -> Result<Prepared, String> {
    let record = load_record(Path::new(&args.source))?;
    let (params, objects) = prepare(&record)?;
    let (name, data) = match &args.object {
        Some(wanted) => objects
            .iter()
            .find(|(n, _)| n == wanted)
            .ok_or_else(|| format!("no object {wanted:?} in {}", record.mesh.display()))?,
        None => objects.first().ok_or("the mesh file holds no object")?,
    };
    let mut without_transfer = params.clone();
    without_transfer.transfer = None;
    let asset = bake_object(&record, &without_transfer, name, data)?;
    let strands = grow_strands(&asset.params.grown_hair(&asset.mesh)).map_err(|e| e.to_string())?;
    let (lo, hi) = bounds(asset.mesh.positions());
    let centre = std::array::from_fn(|k| 0.5 * (lo[k] + hi[k]));
    let radius = 0.5 * (0..3).map(|k| (hi[k] - lo[k]).powi(2)).sum::<f32>().sqrt();
    let reach = radius + asset.params.fur_depth() as f32;
    let (camera, eye) = framing(centre, reach, args.size, args.size);
    let toward_eye: [f32; 3] = std::array::from_fn(|k| eye[k] - centre[k]);
    let lights = vec![ReferenceLight::Sun {
        direction: [toward_eye[0] + reach, toward_eye[1], toward_eye[2] + reach],
        strength: std::f32::consts::PI,
        color: [1.0; 3],
    }];
    let fur = Fur {
        mesh: asset.mesh.clone(),
        patches: asset.patches.clone(),
        strands,
        volume: asset.volume.clone(),
        fur_depth: asset.params.fur_depth(),
    };
    Ok((fur, camera, lights))
}

fn bounds(positions: &[[f32; 3]]) -> ([f32; 3], [f32; 3]) {
    positions
        .iter()
        .fold(([f32::MAX; 3], [f32::MIN; 3]), |(lo, hi), p| {
            (
                std::array::from_fn(|k| lo[k].min(p[k])),
                std::array::from_fn(|k| hi[k].max(p[k])),
            )
        })
}
