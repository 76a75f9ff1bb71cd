//! A GLB reader written for the tests from the glTF 2.0 specification (§4 container, §3.6
//! accessors), on `serde_json::Value`, so the export is checked without its own types.

use serde_json::Value;

/// A parsed GLB: the JSON document and the BIN chunk.
pub(super) struct Glb {
    pub json: Value,
    pub bin: Vec<u8>,
}

fn word(b: &[u8], at: usize) -> u32 {
    u32::from_le_bytes(b[at..at + 4].try_into().unwrap())
}

impl Glb {
    pub fn parse(bytes: &[u8]) -> Glb {
        assert_eq!(&bytes[..4], b"glTF");
        assert_eq!(word(bytes, 4), 2);
        assert_eq!(word(bytes, 8) as usize, bytes.len());
        let json_len = word(bytes, 12) as usize;
        assert_eq!(&bytes[16..20], b"JSON");
        assert_eq!(json_len % 4, 0);
        let json: Value = serde_json::from_slice(&bytes[20..20 + json_len]).unwrap();
        let at = 20 + json_len;
        let bin_len = word(bytes, at) as usize;
        assert_eq!(&bytes[at + 4..at + 8], b"BIN\0");
        assert_eq!(at + 8 + bin_len, bytes.len());
        assert_eq!(
            json["buffers"][0]["byteLength"].as_u64().unwrap() as usize,
            bin_len
        );
        Glb {
            json,
            bin: bytes[at + 8..].to_vec(),
        }
    }

    fn view(&self, index: usize) -> &[u8] {
        let view = &self.json["bufferViews"][index];
        let offset = view["byteOffset"].as_u64().unwrap_or(0) as usize;
        let length = view["byteLength"].as_u64().unwrap() as usize;
        assert_eq!(offset % 4, 0, "views start 4-byte aligned");
        &self.bin[offset..offset + length]
    }

    /// A float accessor's elements, `width` components each (tightly packed views only, which
    /// is all the export writes: it never sets `byteStride`).
    pub fn floats(&self, accessor: usize) -> Vec<Vec<f32>> {
        let a = &self.json["accessors"][accessor];
        assert_eq!(a["componentType"], 5126);
        let width = match a["type"].as_str().unwrap() {
            "SCALAR" => 1,
            "VEC2" => 2,
            "VEC3" => 3,
            "VEC4" => 4,
            "MAT4" => 16,
            other => panic!("type {other}"),
        };
        let count = a["count"].as_u64().unwrap() as usize;
        let data = self.view(a["bufferView"].as_u64().unwrap() as usize);
        assert_eq!(data.len(), count * width * 4);
        data.chunks_exact(4 * width)
            .map(|e| {
                e.chunks_exact(4)
                    .map(|c| f32::from_le_bytes(c.try_into().unwrap()))
                    .collect()
            })
            .collect()
    }

    /// An unsigned-short VEC4 accessor's elements (`JOINTS_0`).
    pub fn joints(&self, accessor: usize) -> Vec<[u16; 4]> {
        let a = &self.json["accessors"][accessor];
        assert_eq!(a["componentType"], 5123);
        assert_eq!(a["type"], "VEC4");
        let data = self.view(a["bufferView"].as_u64().unwrap() as usize);
        data.chunks_exact(8)
            .map(|e| std::array::from_fn(|k| u16::from_le_bytes([e[2 * k], e[2 * k + 1]])))
            .collect()
    }

    /// An index accessor's values (`UNSIGNED_INT`).
    pub fn indices(&self, accessor: usize) -> Vec<u32> {
        let a = &self.json["accessors"][accessor];
        assert_eq!(a["componentType"], 5125);
        let data = self.view(a["bufferView"].as_u64().unwrap() as usize);
        data.chunks_exact(4)
            .map(|c| u32::from_le_bytes(c.try_into().unwrap()))
            .collect()
    }

    /// The decoded RGBA8 pixels and size of image `index` (PNG in a buffer view).
    pub fn image(&self, index: usize) -> (Vec<u8>, u32, u32) {
        let image = &self.json["images"][index];
        assert_eq!(image["mimeType"], "image/png");
        let data = self.view(image["bufferView"].as_u64().unwrap() as usize);
        decode_png(data)
    }

    /// The image behind texture `index`.
    pub fn texture_image(&self, texture: usize) -> usize {
        self.json["textures"][texture]["source"].as_u64().unwrap() as usize
    }

    /// Attribute `name` of a primitive.
    pub fn attribute(primitive: &Value, name: &str) -> usize {
        primitive["attributes"][name]
            .as_u64()
            .unwrap_or_else(|| panic!("no {name}")) as usize
    }
}

/// Decodes an 8-bit RGBA PNG with the `image` crate.
pub(super) fn decode_png(data: &[u8]) -> (Vec<u8>, u32, u32) {
    let decoded = image::load_from_memory_with_format(data, image::ImageFormat::Png).unwrap();
    let image::DynamicImage::ImageRgba8(rgba) = decoded else {
        panic!("expected 8-bit RGBA, got {:?}", decoded.color());
    };
    let (width, height) = rgba.dimensions();
    (rgba.into_raw(), width, height)
}
