//! The glTF container: a GLB (12-byte header, JSON chunk, optional BIN chunk; glTF 2.0
//! specification §4) or a JSON `.gltf`, and the bytes of every buffer it names (the GLB's BIN
//! chunk, or files next to the `.gltf`).

use std::path::{Path, PathBuf};

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
                let file = buffer_file(path, uri).map_err(|e| format!("buffer {i} uri {uri:?}: {e}"))?;
                read_bounded(&file, buffer.byte_length.0)
                    .map_err(|e| format!("buffer {i} ({}): {e}", file.display()))?
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

/// The file a buffer's relative `uri` names, inside the folder of the glTF at `path`.
///
/// As Khronos's and Blender's loaders do, a URI is a relative reference: percent-escapes are
/// decoded, and a scheme (`file:`, `http:`), an absolute path, or `..` that leaves the folder is
/// refused, as is a symbolic link that leads out of it. A file may name only its own neighbours.
fn buffer_file(path: &Path, uri: &str) -> Result<PathBuf, String> {
    let decoded = percent_decode(uri)?;
    if decoded.contains(':') || decoded.starts_with(['/', '\\']) {
        return Err("only a relative path inside the file's folder is read".into());
    }
    let mut inside = PathBuf::new();
    for part in decoded.split(['/', '\\']) {
        match part {
            "" | "." => {}
            ".." => {
                if !inside.pop() {
                    return Err("the path leaves the file's folder".into());
                }
            }
            name => inside.push(name),
        }
    }
    let folder = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let file = folder.join(&inside);
    // A link inside the folder may still point out of it: compare the resolved paths.
    let (real_folder, real_file) = (folder.canonicalize(), file.canonicalize());
    if let (Ok(real_folder), Ok(real_file)) = (real_folder, real_file)
        && !real_file.starts_with(&real_folder)
    {
        return Err("the path leads out of the file's folder through a link".into());
    }
    Ok(file)
}

/// `uri` with its `%XX` escapes decoded (RFC 3986 §2.1); a malformed escape or bytes that are not
/// UTF-8 are an error.
fn percent_decode(uri: &str) -> Result<String, String> {
    let bytes = uri.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = bytes
                .get(i + 1..i + 3)
                .and_then(|h| std::str::from_utf8(h).ok())
                .and_then(|h| u8::from_str_radix(h, 16).ok())
                .ok_or("a malformed %-escape")?;
            out.push(hex);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    String::from_utf8(out).map_err(|_| "the decoded path is not UTF-8".into())
}

/// The first `declared` bytes of `file` (plus one, so that a short file is still told apart),
/// without reading a file that is larger than the buffer it stands for into memory.
fn read_bounded(file: &Path, declared: u64) -> std::io::Result<Vec<u8>> {
    use std::io::Read;
    let mut data = Vec::new();
    std::fs::File::open(file)?.take(declared).read_to_end(&mut data)?;
    Ok(data)
}

/// Runs `gltf-json`'s validation (references in range, known enum values, supported required
/// extensions) and reports the first problem with its JSON path.
fn check(root: &json::Root) -> Result<(), String> {
    use json::validation::Validate;
    // gltf-json indexes the accessor of every POSITION without a bounds check: look first.
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            let position = primitive
                .attributes
                .get(&json::validation::Checked::Valid(json::mesh::Semantic::Positions));
            if let Some(a) = position.filter(|a| a.value() >= root.accessors.len()) {
                return Err(format!(
                    "invalid glTF: meshes[{m}].primitives[{p}].attributes.POSITION names accessor {}, which does not exist",
                    a.value()
                ));
            }
        }
    }
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
