//! Reading a light probe: a latitude–longitude image of the light around the object, for the SH
//! projection ([`crate::prt::sh::project_equirect`]) and the reference renderer's environment.
//! Radiance HDR and OpenEXR hold linear radiance; PNG is decoded from sRGB. The `image` crate
//! decodes, within Pelt's memory limit, which is checked from the header before any pixel is
//! read.

use std::path::Path;

use image::{ImageFormat, ImageReader, Limits};

use super::color::srgb_to_linear;
use crate::error::{Num, PeltError, Result};

/// Bytes a decode may hold per pixel: the decoder's RGBA f32 and Pelt's RGB f32.
const DECODE_BYTES_PER_PIXEL: f64 = 28.0;

/// A decoded image in linear light, RGB rows from the top.
#[derive(Debug, Clone, PartialEq)]
pub struct LinearRgb {
    pub width: usize,
    pub height: usize,
    /// `width · height · 3` finite, non-negative values.
    pub rgb: Vec<f32>,
}

/// Reads the light probe at `path` (`.hdr`, `.exr` or `.png`, told apart by their contents).
///
/// # Errors
/// [`PeltError::Io`] when the file cannot be read or decoded, [`PeltError::InvalidParameter`]
/// naming `environment` for another format or a pixel that is negative or not finite,
/// [`PeltError::MemoryLimit`] when decoding it would pass the memory limit.
pub fn read_light_probe(path: &Path) -> Result<LinearRgb> {
    let io = |source: std::io::Error| PeltError::Io {
        path: path.display().to_string(),
        source,
    };
    let decoding = |e: image::ImageError| io(std::io::Error::other(e));
    let open = || ImageReader::open(path)?.with_guessed_format();
    let format = open().map_err(io)?.format();
    let srgb = match format {
        Some(ImageFormat::Hdr | ImageFormat::OpenExr) => false,
        Some(ImageFormat::Png) => true,
        other => {
            return Err(PeltError::parameter(
                "environment",
                format!(
                    "{} must be a Radiance HDR, OpenEXR or PNG image, got {}",
                    path.display(),
                    other.map_or("an unknown format".into(), |f| format!("{f:?}"))
                ),
            ));
        }
    };
    let (width, height) = open().map_err(io)?.into_dimensions().map_err(decoding)?;
    let pixels = f64::from(width) * f64::from(height);
    crate::memory::check("light probe", pixels * DECODE_BYTES_PER_PIXEL, || {
        format!("a smaller environment image than {width}×{height}")
    })?;
    let mut reader = open().map_err(io)?;
    let mut limits = Limits::default();
    limits.max_alloc = Some(crate::memory::limit());
    reader.limits(limits);
    let image = reader.decode().map_err(decoding)?.into_rgb32f();
    let rgb: Vec<f32> = if srgb {
        image.into_raw().into_iter().map(srgb_to_linear).collect()
    } else {
        image.into_raw()
    };
    if let Some(i) = rgb.iter().position(|v| !(v.is_finite() && *v >= 0.0)) {
        let pixel = i / 3;
        return Err(PeltError::parameter(
            "environment",
            format!(
                "{}: pixel ({}, {}) channel {} must be a finite radiance >= 0, got {}",
                path.display(),
                pixel % width as usize,
                pixel / width as usize,
                i % 3,
                Num(f64::from(rgb[i]))
            ),
        ));
    }
    Ok(LinearRgb {
        width: width as usize,
        height: height as usize,
        rgb,
    })
}
