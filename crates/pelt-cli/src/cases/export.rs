//! Bench cases of the image writers, on the default shell stack (128² × 16 RGBA) baked from the
//! default hair. The file sizes go into each case's `size` text: they depend on the content.

use half::f16;

use super::{BenchOptions, CaseResult, time_fallible};
use pelt_core::error::Result;
use pelt_core::export::{
    ExrCompression, ExrOptions, Ktx2Format, Ktx2Texture, PngOptions, write_exr, write_ktx2, write_png,
};
use pelt_core::hair::HairParams;
use pelt_core::texture::color::srgb8_to_linear_table;
use pelt_core::texture::{AtlasLayout, ImageRef, MipOptions, pack_atlas};
use pelt_core::volume::{VolumeParams, bake_volume};

const RES: usize = 128;
const LAYERS: usize = 16;

/// `export.png.atlas`, `export.exr.f16` and `export.ktx2.array`: the stack as a 4 × 4 atlas PNG,
/// its middle layer as a ZIP-compressed half-float EXR, and the stack as an sRGB KTX2 array with
/// a full mip chain (mipmapping included in the time).
pub(super) fn export_writers(options: &BenchOptions) -> Result<Vec<CaseResult>> {
    let params = VolumeParams {
        resolution: RES,
        layers: LAYERS,
        trim: false,
        lod: false,
        mipmaps: false,
        ..VolumeParams::default()
    };
    let bytes = bake_volume(&HairParams::default(), &params, None)?.shells;
    let reps = if options.quick { 5 } else { 21 };

    let layout = AtlasLayout::new(LAYERS, RES)?;
    let png = || -> Result<Vec<u8>> {
        let atlas = pack_atlas(&layout, 4, &bytes)?;
        let mut out = Vec::new();
        write_png(&mut out, &atlas.view(), &PngOptions::default())?;
        Ok(out)
    };
    let png_size = png()?.len();
    let png_timing = time_fallible(reps, png)?;

    // The middle layer in linear light (sRGB color decoded, alpha as is), as a float texture.
    let linear = srgb8_to_linear_table();
    let middle: Vec<f16> = bytes[LAYERS / 2 * RES * RES * 4..][..RES * RES * 4]
        .chunks_exact(4)
        .flat_map(|p| {
            [
                linear[p[0] as usize],
                linear[p[1] as usize],
                linear[p[2] as usize],
                f32::from(p[3]) / 255.0,
            ]
        })
        .map(f16::from_f32)
        .collect();
    let layer = ImageRef::new(RES, RES, 4, &middle)?;
    let exr = |compression| -> Result<Vec<u8>> {
        let mut out = Vec::new();
        let options = ExrOptions {
            compression,
            ..ExrOptions::default()
        };
        write_exr(&mut out, &layer, &options)?;
        Ok(out)
    };
    let exr_size = exr(ExrCompression::Zip)?.len();
    let exr_raw_size = exr(ExrCompression::None)?.len();
    let exr_timing = time_fallible(reps, || exr(ExrCompression::Zip))?;

    let ktx2 = || -> Result<Vec<u8>> {
        let texture = Ktx2Texture::from_rgba8(
            Ktx2Format::Rgba8Srgb,
            RES,
            RES,
            Some(LAYERS),
            &bytes,
            &MipOptions::default(),
        )?;
        let mut out = Vec::new();
        write_ktx2(&mut out, &texture)?;
        Ok(out)
    };
    let ktx2_size = ktx2()?.len();
    let ktx2_timing = time_fallible(reps, ktx2)?;

    Ok(vec![
        CaseResult::timed(
            "export.png.atlas",
            format!(
                "{RES}x{RES}x{LAYERS} RGBA8 as {}x{} atlas: {png_size} bytes (raw {})",
                layout.width,
                layout.height,
                layout.width * layout.height * 4
            ),
            png_timing,
        ),
        CaseResult::timed(
            "export.exr.f16",
            format!("{RES}x{RES} RGBA f16, ZIP: {exr_size} bytes (uncompressed file {exr_raw_size})"),
            exr_timing,
        ),
        CaseResult::timed(
            "export.ktx2.array",
            format!("{RES}x{RES}x{LAYERS} RGBA8 sRGB + 8 mip levels: {ktx2_size} bytes"),
            ktx2_timing,
        ),
    ])
}
