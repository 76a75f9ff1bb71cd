//! Bench cases of the image writers, on a default-sized shell stack (128² × 16 RGBA). The file
//! sizes go into each case's `size` text: they depend on the content, so the stack is a stand-in
//! for the shell bake of issue 3 built from real strands (below) rather than noise or a constant.

use half::f16;

use super::{BenchOptions, CaseResult, time_fallible};
use crate::error::Result;
use crate::export::{
    AtlasLayout, ExrCompression, ExrOptions, ImageRef, Ktx2Format, Ktx2Texture, MipOptions, PngOptions,
    pack_atlas, write_exr, write_ktx2, write_png,
};
use crate::hair::{HairParams, Strand, grow_strands};
use crate::volume::coverage::{CoverageMode, disk_texel_coverage};

const RES: usize = 128;
const LAYERS: usize = 16;

/// `export.png.atlas`, `export.exr.f16` and `export.ktx2.array`: the stack as a 4 × 4 atlas PNG,
/// its middle layer as a ZIP-compressed half-float EXR, and the stack as an sRGB KTX2 array with
/// a full mip chain (mipmapping included in the time).
pub(super) fn export_writers(options: &BenchOptions) -> Result<Vec<CaseResult>> {
    let (bytes, floats) = synthetic_shells()?;
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

    let middle: Vec<f16> = floats[LAYERS / 2 * RES * RES * 4..][..RES * RES * 4]
        .iter()
        .map(|&v| f16::from_f32(v))
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

/// Layer-major RGBA of the default strands (bytes and linear floats): layer 0 is the opaque skin
/// in the mean root color, layer `l` holds every strand's cross-section at height `l / LAYERS`
/// with exact coverage, colored from root to tip, alpha = coverage (clamped to 1), color straight.
fn synthetic_shells() -> Result<(Vec<u8>, Vec<f32>)> {
    let params = HairParams::default();
    let strands = grow_strands(&params)?;
    let mut rgba = vec![0.0f32; LAYERS * RES * RES * 4];
    for (l, layer) in rgba.chunks_exact_mut(RES * RES * 4).enumerate() {
        if l == 0 {
            for texel in layer.chunks_exact_mut(4) {
                texel[..3].copy_from_slice(&params.root_color);
                texel[3] = 1.0;
            }
            continue;
        }
        let z = l as f64 / LAYERS as f64;
        for strand in &strands {
            let Some((x, y, r, t)) = cross_section(strand, z) else {
                continue;
            };
            let color: [f32; 3] = std::array::from_fn(|k| {
                strand.root_color[k] + t * (strand.tip_color[k] - strand.root_color[k])
            });
            disk_texel_coverage(RES, x, y, r, CoverageMode::Exact, |texel, share| {
                let p = &mut layer[texel * 4..texel * 4 + 4];
                for k in 0..3 {
                    p[k] += share as f32 * color[k];
                }
                p[3] += share as f32;
            })?;
        }
        for p in layer.chunks_exact_mut(4) {
            if p[3] > 0.0 {
                let coverage = p[3];
                p[..3].iter_mut().for_each(|c| *c /= coverage);
                p[3] = coverage.min(1.0);
            }
        }
    }
    let bytes = rgba
        .iter()
        .map(|v| (v.clamp(0.0, 1.0) * 255.0).round() as u8)
        .collect();
    Ok((bytes, rgba))
}

/// Where `strand` crosses height `z`: centre, radius and the share `t` of its height.
fn cross_section(strand: &Strand, z: f64) -> Option<(f64, f64, f64, f32)> {
    let height = strand.points.last()?[2];
    let i = strand
        .points
        .windows(2)
        .position(|w| w[0][2] <= z && z < w[1][2])?;
    let (a, b) = (strand.points[i], strand.points[i + 1]);
    let s = (z - a[2]) / (b[2] - a[2]);
    let r = strand.radii[i] + s * (strand.radii[i + 1] - strand.radii[i]);
    Some((
        a[0] + s * (b[0] - a[0]),
        a[1] + s * (b[1] - a[1]),
        r,
        (z / height) as f32,
    ))
}
