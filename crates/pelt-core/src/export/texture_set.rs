//! Texture sets: every texture of a bake written into a folder, in the formats asked for, with a
//! [`Manifest`] (`pelt.json`) listing each file's meaning.
//!
//! Per object (`<stem>` its [`ExportInput::file_stem`]):
//!
//! - PNG: `<stem>_layer_<l>.png` per shell layer, `<stem>_shells_atlas.png`,
//!   `<stem>_tangents_atlas.png`, `<stem>_fin.png`, and with a transfer
//!   `<stem>_transfer_<t>.png` (8-bit packing, atlas of the layers);
//! - OpenEXR: `<stem>_density.exr` (coverage, one FLOAT channel, atlas) and with a transfer
//!   `<stem>_transfer_<t>.exr` (float16 RGBA, atlas);
//! - KTX2: `<stem>_shells.ktx2` (2D array, RGBA8 sRGB, the bake's mip chain),
//!   `<stem>_tangents.ktx2` (2D array, RGBA8 UNORM, full chain), `<stem>_fin.ktx2` (2D, RGBA8
//!   sRGB, full chain) and with a transfer `<stem>_transfer.ktx2` (2D array of `T · L` layers,
//!   RGBA16F, full chain).
//!
//! The stack follows Lengyel et al. 2001, §2.2 (shell and fin textures) and §2.4 (mipmaps); the
//! transfer textures the PRT shell-fur paper, §2.3. Each file is encoded and written by one task
//! of Pelt's pool, so a file's bytes do not depend on the thread count, and at most one encoding
//! per worker is held at a time: the peak is that of the largest few files, not of the whole set,
//! and is checked against the memory budget before the first file is encoded.

use std::path::Path;

use rayon::prelude::*;

use super::description::StackDescription;
use super::exr::{ExrOptions, encode_exr};
use super::gltf::{in_object, validate_objects};
use super::input::ExportInput;
use super::ktx2::{Ktx2Format, Ktx2Texture, encode_ktx2};
use super::manifest::{Manifest, ManifestFile, ManifestObject};
use super::stack_png::StackImage;
use crate::error::{PeltError, Result};
use crate::memory;
use crate::mesh::split_at_uv_seams;
use crate::texture::atlas::{AtlasLayout, pack_atlas};
use crate::texture::mip::{MipAlpha, MipOptions};
use crate::threads::{pool, thread_count};

/// Which containers a texture set is written in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TextureFormats {
    /// Per-layer PNGs, atlases, fin, 8-bit transfer atlases.
    pub png: bool,
    /// KTX2 arrays with mipmaps.
    pub ktx2: bool,
    /// OpenEXR float data (density, float16 transfer).
    pub exr: bool,
}

impl Default for TextureFormats {
    fn default() -> Self {
        TextureFormats {
            png: true,
            ktx2: true,
            exr: true,
        }
    }
}

impl TextureFormats {
    /// Parses a comma-separated list of `png`, `ktx2`, `exr` (at least one; repeats allowed).
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] naming `formats` for an unknown or empty list.
    pub fn parse(list: &str) -> Result<Self> {
        let mut formats = TextureFormats {
            png: false,
            ktx2: false,
            exr: false,
        };
        for item in list.split(',').map(str::trim) {
            match item {
                "png" => formats.png = true,
                "ktx2" => formats.ktx2 = true,
                "exr" => formats.exr = true,
                other => {
                    return Err(PeltError::parameter(
                        "formats",
                        format!("{other:?} is not one of png, ktx2, exr (comma-separated)"),
                    ));
                }
            }
        }
        Ok(formats)
    }

    fn any(&self) -> bool {
        self.png || self.ktx2 || self.exr
    }
}

/// One file to encode.
enum Job<'a> {
    Png(StackImage<'a>),
    Density(&'a ExportInput<'a>),
    TransferExr(&'a ExportInput<'a>, usize),
    Ktx2Shells(&'a ExportInput<'a>),
    Ktx2Tangents(&'a ExportInput<'a>),
    Ktx2Fin(&'a ExportInput<'a>),
    Ktx2Transfer(&'a ExportInput<'a>),
}

/// Bytes of a full mip chain over `base` bytes: a third more, and a texel per level and layer for
/// the odd sides that round up.
fn chain_bytes(base: f64, layers: f64, texel: f64) -> f64 {
    base * 4.0 / 3.0 + 32.0 * layers * texel
}

impl Job<'_> {
    /// Estimated peak bytes of encoding this file: its input copies (atlas, mip chain), the
    /// encoder's working buffers and its output, from the sizes alone (checked against the
    /// measured peaks in `tests/memory_estimates.rs`).
    fn peak_bytes(&self) -> f64 {
        let atlas = |layers: usize, resolution: usize| {
            AtlasLayout::new(layers, resolution).map_or(f64::INFINITY, |a| (a.width * a.height) as f64)
        };
        match *self {
            // An image (or atlas) copy, the encoder's filtered rows, and a growing output.
            Job::Png(image) => 4.0 * 4.0 * image.texels() as f64,
            // Atlas, the encoder's interleaved copy and its zlib output.
            Job::Density(input) => 5.0 * 4.0 * atlas(input.volume.layers, input.volume.resolution),
            Job::TransferExr(input, _) => {
                let (l, r) = input
                    .transfer
                    .map_or((1, 1), |t| (t.f16.layers, t.f16.resolution));
                5.0 * 8.0 * atlas(l, r)
            }
            // The levels (cloned or generated) and the file that holds them.
            Job::Ktx2Shells(input) | Job::Ktx2Tangents(input) => {
                let v = input.volume;
                let base = 4.0 * (v.layers * v.resolution * v.resolution) as f64;
                3.0 * chain_bytes(base, v.layers as f64, 4.0)
            }
            Job::Ktx2Fin(input) => {
                let [w, h] = input.volume.fin_size;
                3.0 * chain_bytes(4.0 * (w * h) as f64, 1.0, 4.0)
            }
            // Half floats: the chain, its bytes, one level's finiteness check and the file.
            Job::Ktx2Transfer(input) => input.transfer.map_or(0.0, |t| {
                let p = t.f16;
                let layers = (p.textures * p.layers) as f64;
                let base = 8.0 * layers * (p.resolution * p.resolution) as f64;
                4.0 * chain_bytes(base, layers, 8.0) + base
            }),
        }
    }

    fn encode(&self) -> Result<Vec<u8>> {
        match *self {
            Job::Png(image) => image.encode(),
            Job::Density(input) => {
                let v = input.volume;
                let layout = AtlasLayout::new(v.layers, v.resolution)?;
                let atlas = pack_atlas(&layout, 1, &v.coverage)?;
                encode_exr(&atlas.view(), &ExrOptions::default())
            }
            Job::TransferExr(input, t) => {
                let Some(transfer) = &input.transfer else {
                    return Err(PeltError::Internal("transfer job without a transfer".into()));
                };
                let p = transfer.f16;
                let size = 4 * p.layers * p.resolution * p.resolution;
                let layout = AtlasLayout::new(p.layers, p.resolution)?;
                let atlas = pack_atlas(&layout, 4, &p.texels[t * size..(t + 1) * size])?;
                encode_exr(&atlas.view(), &ExrOptions::default())
            }
            Job::Ktx2Shells(input) => {
                let v = input.volume;
                let texture = if v.mips.is_empty() {
                    let options = MipOptions::default();
                    Ktx2Texture::from_rgba8(
                        Ktx2Format::Rgba8Srgb,
                        v.resolution,
                        v.resolution,
                        Some(v.layers),
                        &v.shells,
                        &options,
                    )?
                } else {
                    // The bake's own chain: the one the renderer samples.
                    let levels = std::iter::once(&v.shells).chain(&v.mips).cloned().collect();
                    Ktx2Texture::new(
                        Ktx2Format::Rgba8Srgb,
                        v.resolution,
                        v.resolution,
                        Some(v.layers),
                        levels,
                    )?
                };
                Ok(encode_ktx2(&texture))
            }
            Job::Ktx2Tangents(input) => {
                let v = input.volume;
                // Alpha-weighted like the shells: texels without hair do not pull directions in.
                let texture = Ktx2Texture::from_rgba8(
                    Ktx2Format::Rgba8Unorm,
                    v.resolution,
                    v.resolution,
                    Some(v.layers),
                    &v.tangents,
                    &MipOptions::default(),
                )?;
                Ok(encode_ktx2(&texture))
            }
            Job::Ktx2Fin(input) => {
                let v = input.volume;
                let [w, h] = v.fin_size;
                let texture = Ktx2Texture::from_rgba8(
                    Ktx2Format::Rgba8Srgb,
                    w,
                    h,
                    None,
                    &v.fin,
                    &MipOptions::default(),
                )?;
                Ok(encode_ktx2(&texture))
            }
            Job::Ktx2Transfer(input) => {
                let Some(transfer) = &input.transfer else {
                    return Err(PeltError::Internal("transfer job without a transfer".into()));
                };
                let p = transfer.f16;
                // Coefficients are not color over alpha: every channel is averaged on its own.
                let options = MipOptions {
                    alpha: MipAlpha::Independent,
                    ..MipOptions::default()
                };
                let texture = Ktx2Texture::from_rgba16f(
                    p.resolution,
                    p.resolution,
                    Some(p.textures * p.layers),
                    &p.texels,
                    &options,
                )?;
                Ok(encode_ktx2(&texture))
            }
        }
    }
}

/// Fields of a manifest entry that vary by file.
struct Entry {
    path: String,
    kind: &'static str,
    format: &'static str,
    pixel_format: &'static str,
    srgb: bool,
    size: [usize; 2],
    layers: Option<usize>,
    layer: Option<usize>,
    texture: Option<usize>,
    levels: usize,
    layout: &'static str,
    meaning: String,
}

impl Entry {
    fn manifest_file(self, bytes: u64) -> ManifestFile {
        ManifestFile {
            path: self.path,
            kind: self.kind.into(),
            format: self.format.into(),
            pixel_format: Some(self.pixel_format.into()),
            color_space: Some(if self.srgb { "srgb" } else { "linear" }.into()),
            width: Some(self.size[0]),
            height: Some(self.size[1]),
            layers: self.layers,
            layer: self.layer,
            texture: self.texture,
            levels: Some(self.levels),
            layout: Some(self.layout.into()),
            mode: None,
            bytes,
            meaning: self.meaning,
        }
    }
}

/// The jobs and manifest entries of one object, in file order.
fn plan<'a>(input: &'a ExportInput<'a>, formats: TextureFormats) -> Result<Vec<(Job<'a>, Entry)>> {
    let v = input.volume;
    let stem = input.file_stem();
    let (l, r) = (v.layers, v.resolution);
    let atlas = AtlasLayout::new(l, r)?;
    let [fw, fh] = v.fin_size;
    let textures = input.transfer.map_or(0, |t| t.u8.textures);
    let entry = |path: String, kind, format, pixel_format, srgb, size, layout, meaning: String| Entry {
        path,
        kind,
        format,
        pixel_format,
        srgb,
        size,
        layers: None,
        layer: None,
        texture: None,
        levels: 1,
        layout,
        meaning,
    };
    let mut out = Vec::new();
    if formats.png {
        for layer in 0..l {
            let mut e = entry(
                format!("{stem}_layer_{layer:03}.png"),
                "shell_layer",
                "png",
                "RGBA8_SRGB",
                true,
                [r, r],
                "single",
                format!("shell layer {layer} of {l} (0 = opaque skin): hair color and coverage"),
            );
            e.layer = Some(layer);
            out.push((Job::Png(StackImage::Layer(v, layer)), e));
        }
        let mut e = entry(
            format!("{stem}_shells_atlas.png"),
            "shell_atlas",
            "png",
            "RGBA8_SRGB",
            true,
            [atlas.width, atlas.height],
            "atlas",
            "every shell layer in one image (stack.atlas gives each layer's cell)".into(),
        );
        e.layers = Some(l);
        out.push((Job::Png(StackImage::ShellAtlas(v)), e));
        let mut e = entry(
            format!("{stem}_tangents_atlas.png"),
            "tangent_atlas",
            "png",
            "RGBA8_UNORM",
            false,
            [atlas.width, atlas.height],
            "atlas",
            "hair direction per texel, rgb = 0.5 * d + 0.5 (x, y along the tile, z up), alpha as \
             the shells"
                .into(),
        );
        e.layers = Some(l);
        out.push((Job::Png(StackImage::TangentAtlas(v)), e));
        out.push((
            Job::Png(StackImage::Fin(v)),
            entry(
                format!("{stem}_fin.png"),
                "fin",
                "png",
                "RGBA8_SRGB",
                true,
                [fw, fh],
                "single",
                "fin texture: hair seen from the side, row 0 the top of the fur".into(),
            ),
        ));
        if let Some(transfer) = &input.transfer {
            for t in 0..textures {
                let mut e = entry(
                    format!("{stem}_transfer_{t}.png"),
                    "transfer_atlas",
                    "png",
                    "RGBA8_UNORM",
                    false,
                    [atlas.width, atlas.height],
                    "atlas",
                    format!(
                        "transfer coefficients {}..{} in RGBA, 8-bit: value = byte / 255 * scale + bias \
                         (stack.transfer.scale, bias)",
                        4 * t,
                        (4 * t + 3).min(transfer.order * transfer.order - 1)
                    ),
                );
                e.layers = Some(l);
                e.texture = Some(t);
                out.push((Job::Png(StackImage::Transfer(transfer.u8, t)), e));
            }
        }
    }
    if formats.exr {
        let mut e = entry(
            format!("{stem}_density.exr"),
            "density_atlas",
            "exr",
            "R32F",
            false,
            [atlas.width, atlas.height],
            "atlas",
            "hair coverage per texel (summed cross-section share, can exceed 1): the density of \
             the transfer bake; channel Y"
                .into(),
        );
        e.layers = Some(l);
        out.push((Job::Density(input), e));
        for t in 0..textures {
            let mut e = entry(
                format!("{stem}_transfer_{t}.exr"),
                "transfer_atlas",
                "exr",
                "RGBA16F",
                false,
                [atlas.width, atlas.height],
                "atlas",
                format!("transfer coefficients {}..{} in RGBA, float16", 4 * t, 4 * t + 3),
            );
            e.layers = Some(l);
            e.texture = Some(t);
            out.push((Job::TransferExr(input, t), e));
        }
    }
    if formats.ktx2 {
        let full = |w: usize, h: usize| crate::texture::mip::full_mip_count(w, h);
        let mut e = entry(
            format!("{stem}_shells.ktx2"),
            "shell_array",
            "ktx2",
            "RGBA8_SRGB",
            true,
            [r, r],
            "array",
            "every shell layer as a 2D array layer, with the mip chain the renderer samples".into(),
        );
        e.layers = Some(l);
        e.levels = if v.mips.is_empty() {
            full(r, r)
        } else {
            1 + v.mips.len()
        };
        out.push((Job::Ktx2Shells(input), e));
        let mut e = entry(
            format!("{stem}_tangents.ktx2"),
            "tangent_array",
            "ktx2",
            "RGBA8_UNORM",
            false,
            [r, r],
            "array",
            "hair direction per texel, rgb = 0.5 * d + 0.5, one array layer per shell layer".into(),
        );
        e.layers = Some(l);
        e.levels = full(r, r);
        out.push((Job::Ktx2Tangents(input), e));
        let mut e = entry(
            format!("{stem}_fin.ktx2"),
            "fin",
            "ktx2",
            "RGBA8_SRGB",
            true,
            [fw, fh],
            "single",
            "fin texture with its mip chain, row 0 the top of the fur".into(),
        );
        e.levels = full(fw, fh);
        out.push((Job::Ktx2Fin(input), e));
        if input.transfer.is_some() {
            let mut e = entry(
                format!("{stem}_transfer.ktx2"),
                "transfer_array",
                "ktx2",
                "RGBA16F",
                false,
                [r, r],
                "texture_major_array",
                format!(
                    "transfer coefficients, float16: array layer t * {l} + l holds coefficients \
                     4t..4t + 3 of stack layer l"
                ),
            );
            e.layers = Some(textures * l);
            e.levels = full(r, r);
            out.push((Job::Ktx2Transfer(input), e));
        }
    }
    Ok(out)
}

/// Writes the texture set of `objects` into `folder` (created if missing) and returns its
/// manifest, also saved there as `pelt.json`. The files are written beside `folder` and moved in
/// when all are written ([`super::StagedFolder`]): a failure leaves `folder` as it was.
///
/// # Errors
/// [`PeltError::InvalidParameter`] naming `formats` when none is chosen, `objects` when two
/// objects share a file stem, or an object's field (see [`ExportInput::validate`]);
/// [`PeltError::Io`] naming the file that could not be written.
pub fn write_texture_set(
    objects: &[ExportInput<'_>],
    folder: &Path,
    formats: TextureFormats,
) -> Result<Manifest> {
    let staged = super::StagedFolder::new(folder)?;
    let manifest = texture_set(objects, staged.path(), formats)?;
    manifest.save(staged.path())?;
    staged.commit(&manifest.paths())?;
    Ok(manifest)
}

/// [`write_texture_set`] without saving the manifest (callers that add files to it first).
pub(crate) fn texture_set(
    objects: &[ExportInput<'_>],
    folder: &Path,
    formats: TextureFormats,
) -> Result<Manifest> {
    if !formats.any() {
        return Err(PeltError::parameter(
            "formats",
            "must name at least one of png, ktx2, exr",
        ));
    }
    validate_objects(objects)?;
    check_memory(objects, formats)?;
    let stems: Vec<String> = objects.iter().map(ExportInput::file_stem).collect();
    for (i, stem) in stems.iter().enumerate() {
        if let Some(j) = stems[..i].iter().position(|s| s == stem) {
            return Err(PeltError::parameter(
                "objects",
                format!(
                    "objects {j} ({:?}) and {i} ({:?}) would write the same files ({stem}_*)",
                    objects[j].name, objects[i].name
                ),
            ));
        }
    }
    std::fs::create_dir_all(folder).map_err(|source| PeltError::Io {
        path: folder.display().to_string(),
        source,
    })?;
    let mut manifest = Manifest::new();
    for (i, input) in objects.iter().enumerate() {
        let object = write_object(input, folder, formats).map_err(|e| in_object(i, input.name, e))?;
        manifest.objects.push(object);
    }
    Ok(manifest)
}

/// Estimated peak bytes of writing `input`'s files in `formats`: the encodings of the largest
/// files that Pelt's workers may hold at once.
///
/// # Errors
/// As [`AtlasLayout::new`] for a volume without layers.
pub fn texture_set_peak_bytes(input: &ExportInput<'_>, formats: TextureFormats) -> Result<f64> {
    let mut peaks: Vec<f64> = plan(input, formats)?
        .iter()
        .map(|(job, _)| job.peak_bytes())
        .collect();
    peaks.sort_unstable_by(|a, b| b.total_cmp(a));
    Ok(peaks.iter().take(thread_count().max(1)).sum())
}

/// `Ok` when every object's [`texture_set_peak_bytes`] fits the memory limit; otherwise
/// [`PeltError::MemoryLimit`] naming the sizes to lower.
fn check_memory(objects: &[ExportInput<'_>], formats: TextureFormats) -> Result<()> {
    for (i, input) in objects.iter().enumerate() {
        let bytes = texture_set_peak_bytes(input, formats).map_err(|e| in_object(i, input.name, e))?;
        let v = input.volume;
        memory::check("write_texture_set", bytes, || {
            format!(
                "the volume's `resolution` ({}) or `layers` ({}), the transfer's `order`, or \
                 write fewer `formats`",
                v.resolution, v.layers
            )
        })?;
    }
    Ok(())
}

/// Encodes and writes one object's files in parallel, each by the task that encoded it.
fn write_object(input: &ExportInput<'_>, folder: &Path, formats: TextureFormats) -> Result<ManifestObject> {
    let uv_scale = split_at_uv_seams(input.mesh, input.corner_uvs)?.uv_scale;
    let stack = StackDescription::new(input, uv_scale)?;
    let planned = plan(input, formats)?;
    let sizes: Vec<u64> = pool().install(|| {
        planned
            .par_iter()
            .map(|(job, entry)| {
                let bytes = job.encode()?;
                let path = folder.join(&entry.path);
                std::fs::write(&path, &bytes).map_err(|source| PeltError::Io {
                    path: path.display().to_string(),
                    source,
                })?;
                Ok(bytes.len() as u64)
            })
            .collect::<Result<_>>()
    })?;
    let files = planned
        .into_iter()
        .zip(sizes)
        .map(|((_, entry), bytes)| entry.manifest_file(bytes))
        .collect();
    Ok(ManifestObject {
        name: input.name.into(),
        stack,
        files,
    })
}
