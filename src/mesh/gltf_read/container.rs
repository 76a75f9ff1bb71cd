//! The glTF container: a GLB (12-byte header, JSON chunk, optional BIN chunk; glTF 2.0
//! specification §4) or a JSON `.gltf`, and the bytes of every buffer it names (the GLB's BIN
//! chunk, or files next to the `.gltf`).

use std::path::Path;

use gltf_json as json;

/// `glTF` in ASCII, little-endian.
const GLB_MAGIC: u32 = 0x4654_6C67;
/// Chunk type of the JSON document.
const CHUNK_JSON: u32 = 0x4E4F_534A;
/// Chunk type of the binary buffer.
const CHUNK_BIN: u32 = 0x004E_4942;

/// A parsed file: the document and its buffers' bytes, buffer `i` at index `i`.
pub(super) struct Document {
    pub root: json::Root,
    pub buffers: Vec<Vec<u8>>,
}

fn word(bytes: &[u8], at: usize) -> Option<u32> {
    let b = bytes.get(at..at + 4)?;
    Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
}

/// A GLB chunk: its type, its data, and where the next chunk starts.
type Chunk<'a> = (u32, &'a [u8], usize);

/// Splits a GLB into its JSON and optional BIN chunk.
fn split_glb(bytes: &[u8]) -> Result<(&[u8], Option<&[u8]>), String> {
    let version = word(bytes, 4).ok_or("truncated GLB header")?;
    if version != 2 {
        return Err(format!(
            "GLB version {version}; only glTF 2.0 (version 2) is supported"
        ));
    }
    let length = word(bytes, 8).ok_or("truncated GLB header")? as usize;
    if length > bytes.len() {
        return Err(format!(
            "the GLB header states {length} bytes but the file has {}",
            bytes.len()
        ));
    }
    let bytes = &bytes[..length];
    let chunk = |at: usize| -> Result<Option<Chunk<'_>>, String> {
        if at >= bytes.len() {
            return Ok(None);
        }
        let len = word(bytes, at).ok_or("truncated GLB chunk header")? as usize;
        let kind = word(bytes, at + 4).ok_or("truncated GLB chunk header")?;
        let data = bytes
            .get(at + 8..at + 8 + len)
            .ok_or_else(|| format!("GLB chunk at byte {at} runs past the end of the file"))?;
        Ok(Some((kind, data, at + 8 + len)))
    };
    let (kind, json, next) = chunk(12)?.ok_or("the GLB has no JSON chunk")?;
    if kind != CHUNK_JSON {
        return Err("the GLB's first chunk is not JSON".into());
    }
    let bin = match chunk(next)? {
        Some((CHUNK_BIN, data, _)) => Some(data),
        _ => None,
    };
    Ok((json, bin))
}

/// Parses `bytes` (GLB or JSON glTF) read from `path`, and loads its buffers.
///
/// Errors are plain messages; the caller names the file.
pub(super) fn parse(path: &Path, bytes: &[u8]) -> Result<Document, String> {
    let (text, bin) = if word(bytes, 0) == Some(GLB_MAGIC) {
        split_glb(bytes)?
    } else {
        (bytes, None)
    };
    let root = json::Root::from_slice(text).map_err(|e| format!("not a glTF 2.0 document: {e}"))?;
    check(&root)?;
    let mut buffers = Vec::with_capacity(root.buffers.len());
    for (i, buffer) in root.buffers.iter().enumerate() {
        let data = match (&buffer.uri, i, bin) {
            (None, 0, Some(bin)) => bin.to_vec(),
            (None, _, _) => return Err(format!("buffer {i} has no uri and is not the GLB's BIN chunk")),
            (Some(uri), _, _) if uri.starts_with("data:") => {
                return Err(format!(
                    "buffer {i} is embedded as a data URI, which Pelt does not read; save the file as .glb"
                ));
            }
            (Some(uri), _, _) => {
                let file = path.parent().unwrap_or(Path::new(".")).join(uri);
                std::fs::read(&file).map_err(|e| format!("buffer {i} ({}): {e}", file.display()))?
            }
        };
        let declared = buffer.byte_length.0;
        if (data.len() as u64) < declared {
            return Err(format!(
                "buffer {i} declares {declared} bytes but holds {}",
                data.len()
            ));
        }
        buffers.push(data);
    }
    Ok(Document { root, buffers })
}

/// Runs `gltf-json`'s validation (references in range, known enum values, supported required
/// extensions) and reports the first problem with its JSON path.
fn check(root: &json::Root) -> Result<(), String> {
    use json::validation::Validate;
    let mut first: Option<String> = None;
    root.validate(root, json::Path::new, &mut |path, error| {
        if first.is_none() {
            first = Some(format!("{}: {error}", path().as_str()));
        }
    });
    match first {
        None => Ok(()),
        Some(problem) => Err(format!("invalid glTF: {problem}")),
    }
}
