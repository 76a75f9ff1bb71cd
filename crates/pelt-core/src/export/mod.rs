//! Export of baked fur for engines and other tools: image writers (PNG, OpenEXR, KTX2) over the
//! images, mips and atlas of [`crate::texture`], glTF 2.0 binaries ([`gltf`]), texture sets ([`texture_set`]) and whole folders with
//! their `pelt.json` manifest ([`asset`], [`manifest`]). Layout and schemas: `docs/export.md`.
//!
//! Lengyel et al. 2001, §2.2 store the shell layers as a stack of RGBA textures. Engines sample
//! them as a 2D-array texture (KTX2, with mipmaps), while Blender materials and many engines have
//! no texture arrays, so the layers are also laid out side by side in one atlas image
//! ([`crate::texture::atlas`]). Float data (coverage, density, transfer coefficients) goes to OpenEXR.
//!
//! Every writer takes an [`ImageRef`] (or a [`Ktx2Texture`]), validates it up front and writes
//! bytes that depend only on its input: no timestamps, no thread-dependent ordering, so the same
//! bake always gives the same files. Colors are written as given: straight (not premultiplied)
//! alpha, in whatever encoding the caller chose; [`PngOptions::srgb`] and [`Ktx2Format`] say which
//! one the file declares.
//!
//! PNG goes through the `png` crate and EXR through `exr`; KTX2 is written by hand from the KTX 2.0
//! specification (the `ktx2` crate only reads), and the tests read it back with that reader.
//!
//! The object-level exports take [`ExportInput`]s (one borrowed, validated object each; a pipeline
//! bake gives one with [`ExportInput::from_asset`]) and describe the stack with
//! [`StackDescription`], shared by the glTF `extras` and the manifest.

pub mod asset;
pub mod description;
pub mod exr;
pub mod gltf;
pub mod input;
pub mod ktx2;
pub mod manifest;
pub mod materials;
mod names;
pub mod png;
pub mod rig;
mod stack_png;
pub mod staging;
pub mod texture_set;

#[cfg(test)]
mod tests;

use crate::error::PeltError;
use staging::save_to_path;

pub use asset::{AssetOptions, write_asset, write_asset_files};
pub use description::StackDescription;
pub use exr::{ExrCompression, ExrOptions, ExrSample, save_exr, write_exr};
pub use gltf::{GltfMode, GltfOptions, encode_glb, glb_peak_bytes, save_glb};
pub use input::{ExportInput, TransferTextures};
pub use ktx2::{Ktx2Format, Ktx2Texture, save_ktx2, write_ktx2};
pub use manifest::{MANIFEST_NAME, Manifest, ManifestFile, ManifestObject};
pub use materials::{MaterialSlots, OwnMaterial};
pub use png::{PngCompression, PngOptions, PngSample, save_png, write_png};
pub use rig::{Animation, Skeleton, SkeletonNode, SkinBinding, Transform, WeightReport};
pub use staging::StagedFolder;
pub use texture_set::{TextureFormats, texture_set_peak_bytes, write_texture_set};

/// The name [`PeltError::Io`] reports for failures of a caller's `Write` (it has no path).
pub const WRITER_NAME: &str = "<writer>";

/// Wraps an I/O error on the caller's writer.
fn writer_error(source: std::io::Error) -> PeltError {
    PeltError::Io {
        path: WRITER_NAME.into(),
        source,
    }
}
