//! A glTF 2.0 binary (GLB) assembled in memory: one binary buffer with a buffer view per accessor
//! or image (each 4-byte aligned), the JSON document built from `gltf-json`'s types, and the
//! container (12-byte header, JSON chunk padded with spaces, BIN chunk padded with zeros), as the
//! glTF 2.0 specification, §4 "GLB File Format Specification", lays it out.
//!
//! Everything is appended in call order and images with identical bytes are stored once, so the
//! same calls always give the same file.

use std::collections::HashMap;

use gltf_json as json;
use json::validation::{Checked, USize64};

use crate::error::{PeltError, Result};

/// `glTF` in ASCII, little-endian.
const GLB_MAGIC: u32 = 0x4654_6C67;
/// Container version.
const GLB_VERSION: u32 = 2;
/// Chunk type of the JSON document (`JSON`).
const CHUNK_JSON: u32 = 0x4E4F_534A;
/// Chunk type of the binary buffer (`BIN\0`).
const CHUNK_BIN: u32 = 0x004E_4942;

/// Sampler kinds the exports use.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub(super) enum SamplerKind {
    /// The shell tile: repeats both ways (UVs leave `[0, 1]`), trilinear.
    Tile,
    /// The fin texture: repeats along the edge (`u`), clamped along the height (`v`).
    Fin,
    /// Atlases and data textures an engine addresses itself: clamped, bilinear, no mipmaps.
    Clamp,
}

/// The document and binary buffer under construction.
pub(super) struct GlbBuilder {
    pub root: json::Root,
    bin: Vec<u8>,
    images: HashMap<Vec<u8>, json::Index<json::Image>>,
    samplers: HashMap<SamplerKind, json::Index<json::texture::Sampler>>,
    /// `(image, sampler)` → texture, so a texture is made once per image.
    textures: HashMap<(u32, SamplerKind), json::Index<json::Texture>>,
}

impl GlbBuilder {
    pub fn new() -> Self {
        let root = json::Root {
            asset: json::Asset {
                generator: Some(format!("pelt {}", crate::VERSION)),
                ..json::Asset::default()
            },
            ..json::Root::default()
        };
        GlbBuilder {
            root,
            bin: Vec::new(),
            images: HashMap::new(),
            samplers: HashMap::new(),
            textures: HashMap::new(),
        }
    }

    /// Bytes in the binary buffer so far.
    pub fn buffer_len(&self) -> usize {
        self.bin.len()
    }

    /// Appends `bytes` to the binary buffer (4-byte aligned) as a new buffer view.
    fn view(
        &mut self,
        bytes: &[u8],
        target: Option<json::buffer::Target>,
    ) -> json::Index<json::buffer::View> {
        self.bin.resize(self.bin.len().next_multiple_of(4), 0);
        let offset = self.bin.len();
        self.bin.extend_from_slice(bytes);
        self.root.push(json::buffer::View {
            buffer: json::Index::new(0),
            byte_length: USize64::from(bytes.len()),
            byte_offset: Some(USize64::from(offset)),
            byte_stride: None,
            name: None,
            target: target.map(Checked::Valid),
            extensions: None,
            extras: None,
        })
    }

    fn accessor(
        &mut self,
        view: json::Index<json::buffer::View>,
        count: usize,
        component: json::accessor::ComponentType,
        kind: json::accessor::Type,
        bounds: Option<(serde_json::Value, serde_json::Value)>,
    ) -> json::Index<json::Accessor> {
        let (min, max) = bounds.unzip();
        self.root.push(json::Accessor {
            buffer_view: Some(view),
            byte_offset: None,
            count: USize64::from(count),
            component_type: Checked::Valid(json::accessor::GenericComponentType(component)),
            extensions: None,
            extras: None,
            type_: Checked::Valid(kind),
            min,
            max,
            name: None,
            normalized: false,
            sparse: None,
        })
    }

    /// A float vertex attribute of `N` components per vertex (`N` in 1..=4). With `bounds` the
    /// accessor states its per-component minimum and maximum (required for `POSITION`).
    pub fn attribute<const N: usize>(
        &mut self,
        values: &[[f32; N]],
        bounds: bool,
    ) -> json::Index<json::Accessor> {
        self.floats(values, bounds, Some(json::buffer::Target::ArrayBuffer))
    }

    /// Float data that is not a vertex attribute (inverse bind matrices, animation samples), `N`
    /// in 1..=4 or 16 (a column-major 4×4 matrix).
    pub fn data<const N: usize>(&mut self, values: &[[f32; N]], bounds: bool) -> json::Index<json::Accessor> {
        self.floats(values, bounds, None)
    }

    fn floats<const N: usize>(
        &mut self,
        values: &[[f32; N]],
        bounds: bool,
        target: Option<json::buffer::Target>,
    ) -> json::Index<json::Accessor> {
        let kind = match N {
            1 => json::accessor::Type::Scalar,
            2 => json::accessor::Type::Vec2,
            3 => json::accessor::Type::Vec3,
            16 => json::accessor::Type::Mat4,
            _ => json::accessor::Type::Vec4,
        };
        let bytes: Vec<u8> = values.iter().flatten().flat_map(|v| v.to_le_bytes()).collect();
        let bounds = bounds.then(|| {
            let mut lo = [f32::INFINITY; N];
            let mut hi = [f32::NEG_INFINITY; N];
            for v in values {
                for k in 0..N {
                    lo[k] = lo[k].min(v[k]);
                    hi[k] = hi[k].max(v[k]);
                }
            }
            (serde_json::json!(lo.to_vec()), serde_json::json!(hi.to_vec()))
        });
        let view = self.view(&bytes, target);
        self.accessor(
            view,
            values.len(),
            json::accessor::ComponentType::F32,
            kind,
            bounds,
        )
    }

    /// `JOINTS_0`: four unsigned-short node indices per vertex.
    pub fn joints(&mut self, values: &[[u16; 4]]) -> json::Index<json::Accessor> {
        let bytes: Vec<u8> = values.iter().flatten().flat_map(|v| v.to_le_bytes()).collect();
        let view = self.view(&bytes, Some(json::buffer::Target::ArrayBuffer));
        self.accessor(
            view,
            values.len(),
            json::accessor::ComponentType::U16,
            json::accessor::Type::Vec4,
            None,
        )
    }

    /// Triangle indices (`u32`).
    pub fn indices(&mut self, indices: &[u32]) -> json::Index<json::Accessor> {
        let bytes: Vec<u8> = indices.iter().flat_map(|v| v.to_le_bytes()).collect();
        let view = self.view(&bytes, Some(json::buffer::Target::ElementArrayBuffer));
        self.accessor(
            view,
            indices.len(),
            json::accessor::ComponentType::U32,
            json::accessor::Type::Scalar,
            None,
        )
    }

    /// A PNG image stored in the buffer, once per distinct content; the first name given wins.
    pub fn png_image(&mut self, name: &str, png: Vec<u8>) -> json::Index<json::Image> {
        if let Some(&index) = self.images.get(&png) {
            return index;
        }
        let view = self.view(&png, None);
        let index = self.root.push(json::Image {
            buffer_view: Some(view),
            mime_type: Some(json::image::MimeType("image/png".into())),
            name: Some(name.into()),
            uri: None,
            extensions: None,
            extras: None,
        });
        self.images.insert(png, index);
        index
    }

    fn sampler(&mut self, kind: SamplerKind) -> json::Index<json::texture::Sampler> {
        if let Some(&index) = self.samplers.get(&kind) {
            return index;
        }
        use json::texture::{MagFilter, MinFilter, WrappingMode};
        let (min, wrap_s, wrap_t) = match kind {
            SamplerKind::Tile => (
                MinFilter::LinearMipmapLinear,
                WrappingMode::Repeat,
                WrappingMode::Repeat,
            ),
            SamplerKind::Fin => (
                MinFilter::LinearMipmapLinear,
                WrappingMode::Repeat,
                WrappingMode::ClampToEdge,
            ),
            SamplerKind::Clamp => (
                MinFilter::Linear,
                WrappingMode::ClampToEdge,
                WrappingMode::ClampToEdge,
            ),
        };
        let index = self.root.push(json::texture::Sampler {
            mag_filter: Some(Checked::Valid(MagFilter::Linear)),
            min_filter: Some(Checked::Valid(min)),
            wrap_s: Checked::Valid(wrap_s),
            wrap_t: Checked::Valid(wrap_t),
            ..json::texture::Sampler::default()
        });
        self.samplers.insert(kind, index);
        index
    }

    /// A texture of `image` with the sampler of `kind`, once per pair.
    pub fn texture(
        &mut self,
        image: json::Index<json::Image>,
        kind: SamplerKind,
    ) -> json::Index<json::Texture> {
        let key = (image.value() as u32, kind);
        if let Some(&index) = self.textures.get(&key) {
            return index;
        }
        let sampler = self.sampler(kind);
        let index = self.root.push(json::Texture {
            name: None,
            sampler: Some(sampler),
            source: image,
            extensions: None,
            extras: None,
        });
        self.textures.insert(key, index);
        index
    }

    /// The GLB file: header, JSON chunk, BIN chunk.
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] naming `objects` when the file would exceed the 4 GiB a
    /// GLB header can state; [`PeltError::Internal`] if the document cannot be serialized.
    pub fn finish(mut self) -> Result<Vec<u8>> {
        self.bin.resize(self.bin.len().next_multiple_of(4), 0);
        if !self.bin.is_empty() {
            self.root.buffers = vec![json::Buffer {
                byte_length: USize64::from(self.bin.len()),
                name: None,
                uri: None,
                extensions: None,
                extras: None,
            }];
        }
        let text = self
            .root
            .to_vec()
            .map_err(|e| PeltError::Internal(format!("glTF JSON: {e}")))?;
        glb_container(&text, &self.bin)
    }
}

/// A GLB file of a JSON document and a binary buffer (glTF 2.0 §4): the 12-byte header, the JSON
/// chunk padded with spaces and, when `bin` is not empty, the BIN chunk padded with zeros.
///
/// # Errors
/// [`PeltError::InvalidParameter`] naming `objects` when the file would pass the 4 GiB a GLB
/// header can state.
pub fn glb_container(json: &[u8], bin: &[u8]) -> Result<Vec<u8>> {
    let (text_len, bin_len) = (json.len().next_multiple_of(4), bin.len().next_multiple_of(4));
    let bin_chunk = if bin.is_empty() { 0 } else { 8 + bin_len };
    let total = 12 + 8 + text_len + bin_chunk;
    let too_big = || {
        PeltError::parameter(
            "objects",
            format!(
                "the GLB would hold {total} bytes; a GLB file holds at most {}",
                u32::MAX
            ),
        )
    };
    let total32 = u32::try_from(total).map_err(|_| too_big())?;
    let mut out = Vec::with_capacity(total);
    for word in [GLB_MAGIC, GLB_VERSION, total32, text_len as u32, CHUNK_JSON] {
        out.extend_from_slice(&word.to_le_bytes());
    }
    out.extend_from_slice(json);
    out.resize(20 + text_len, b' ');
    if !bin.is_empty() {
        out.extend_from_slice(&(bin_len as u32).to_le_bytes());
        out.extend_from_slice(&CHUNK_BIN.to_le_bytes());
        out.extend_from_slice(bin);
        out.resize(total, 0);
    }
    Ok(out)
}
