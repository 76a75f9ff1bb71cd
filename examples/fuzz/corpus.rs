//! The `corpus` target: real OBJ, glTF and GLB files, read as they are and corrupted the ways
//! files break (bytes flipped, cut short, spliced, numbers swapped for NaN, huge or negative
//! ones, lines dropped or repeated), then read and turned into a fur mesh as `pelt bake` does.
//!
//! The seed files are the repository's `tests/data` and every `.obj`, `.gltf` and `.glb` under
//! the folders in `PELT_FUZZ_CORPUS` (separated by `:`), for example the Khronos glTF-Validator's
//! test assets and tinyobjloader's models (`docs/reliability.md`). Each seed's folder is copied
//! once into a scratch folder, and a case writes its corrupted file beside those copies, so the
//! buffers and images it names resolve as they would beside the original.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use arbitrary::{Result as Arb, Unstructured};
use pelt::FurMesh;
use pelt::mesh::gltf_read::read_gltf;
use pelt::mesh::obj::{MeshData, read_obj};

use super::{Outcome, all_finite, judge, judge_error};

/// Seeds larger than this are left out (the run is about many corruptions, not big files).
const MAX_SEED_BYTES: u64 = 4 << 20;

/// Numbers a corrupted text may carry instead of one of its own.
const NUMBERS: [&str; 12] = [
    "nan",
    "inf",
    "-inf",
    "1e39",
    "-1",
    "0",
    "-0",
    "1e-45",
    "4294967295",
    "18446744073709551615",
    "99999999999999999999999",
    "2147483648",
];

/// One seed: its bytes and the scratch folder that holds copies of its neighbours.
struct Seed {
    bytes: Vec<u8>,
    kind: Kind,
    folder: PathBuf,
}

#[derive(Clone, Copy, PartialEq)]
enum Kind {
    Obj,
    Gltf,
    Glb,
}

static SEEDS: OnceLock<Vec<Seed>> = OnceLock::new();

fn seeds() -> &'static [Seed] {
    SEEDS.get_or_init(load_seeds)
}

fn kind_of(path: &Path) -> Option<Kind> {
    match path.extension()?.to_str()?.to_ascii_lowercase().as_str() {
        "obj" => Some(Kind::Obj),
        "gltf" => Some(Kind::Gltf),
        "glb" => Some(Kind::Glb),
        _ => None,
    }
}

/// Every seed file under `root`, sorted, so that case numbers replay.
fn files_under(root: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(root) else {
        return;
    };
    let mut paths: Vec<PathBuf> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
    paths.sort();
    for path in paths {
        if path.is_dir() {
            files_under(&path, out);
        } else if kind_of(&path).is_some() && path.metadata().is_ok_and(|m| m.len() <= MAX_SEED_BYTES) {
            out.push(path);
        }
    }
}

fn load_seeds() -> Vec<Seed> {
    let repo = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut roots = vec![repo.join("tests/data")];
    if let Some(extra) = std::env::var_os("PELT_FUZZ_CORPUS") {
        roots.extend(std::env::split_paths(&extra));
    }
    let mut files = Vec::new();
    for root in &roots {
        files_under(root, &mut files);
    }
    let scratch = super::scratch_folder().join("corpus");
    let mut folders: Vec<PathBuf> = Vec::new();
    let mut seeds = Vec::with_capacity(files.len());
    for path in files {
        let (Some(kind), Ok(bytes)) = (kind_of(&path), std::fs::read(&path)) else {
            continue;
        };
        let source = path.parent().unwrap_or(Path::new(".")).to_path_buf();
        let index = folders.iter().position(|f| *f == source).unwrap_or_else(|| {
            folders.push(source.clone());
            folders.len() - 1
        });
        let folder = scratch.join(index.to_string());
        if !folder.exists() {
            copy_files(&source, &folder);
        }
        seeds.push(Seed { bytes, kind, folder });
    }
    seeds
}

/// The plain files of `from` (not its subfolders) into `to`.
fn copy_files(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).expect("a scratch folder");
    for entry in std::fs::read_dir(from).into_iter().flatten().flatten() {
        let path = entry.path();
        if path.is_file() && path.metadata().is_ok_and(|m| m.len() <= MAX_SEED_BYTES) {
            let _ = std::fs::copy(&path, to.join(entry.file_name()));
        }
    }
}

/// One seed, corrupted by up to three mutations (none in one case of eight), read and meshed.
pub fn corpus_target(u: &mut Unstructured<'_>) -> Arb<Outcome> {
    let seeds = seeds();
    if seeds.is_empty() {
        return Ok(Outcome::Failed("no seed files".into()));
    }
    let seed = &seeds[u.choose_index(seeds.len())?];
    let mut bytes = seed.bytes.clone();
    if !u.ratio(1, 8)? {
        for _ in 0..u.int_in_range(1..=3)? {
            bytes = mutate(u, seed.kind, bytes)?;
        }
    }
    let name = match seed.kind {
        Kind::Obj => "case.obj",
        Kind::Gltf => "case.gltf",
        Kind::Glb => "case.glb",
    };
    let path = seed.folder.join(name);
    std::fs::write(&path, &bytes).map_err(|_| arbitrary::Error::IncorrectFormat)?;
    Ok(match seed.kind {
        Kind::Obj => match read_obj(&path) {
            Ok(mesh) => meshed(&[mesh]),
            Err(e) => judge_error(&e),
        },
        Kind::Gltf | Kind::Glb => match read_gltf(&path) {
            Ok(objects) => meshed(&objects.into_iter().map(|o| o.mesh).collect::<Vec<_>>()),
            Err(e) => judge_error(&e),
        },
    })
}

/// The contract for what a reader returned: finite positions, and a fur mesh or a named refusal.
fn meshed(meshes: &[MeshData]) -> Outcome {
    for mesh in meshes {
        if let Err(why) = all_finite("positions", mesh.positions.iter().flatten()) {
            return Outcome::Failed(why);
        }
        if let outcome @ (Outcome::Failed(_) | Outcome::Refused) =
            judge(FurMesh::new(mesh.input()), |_| Ok(()))
        {
            return outcome;
        }
    }
    Outcome::Ok
}

/// One corruption of `bytes`; text-aware ones on OBJ and glTF text and on a GLB's JSON chunk.
fn mutate(u: &mut Unstructured<'_>, kind: Kind, mut bytes: Vec<u8>) -> Arb<Vec<u8>> {
    if bytes.is_empty() {
        let len = u.int_in_range(0..=16)?;
        return Ok(u.bytes(len)?.to_vec());
    }
    match u.int_in_range(0..=5)? {
        // Flipped bytes.
        0 => {
            for _ in 0..u.int_in_range(1..=8)? {
                let at = u.choose_index(bytes.len())?;
                bytes[at] = u.arbitrary()?;
            }
        }
        // Cut short.
        1 => bytes.truncate(u.choose_index(bytes.len())?),
        // Random bytes spliced in.
        2 => {
            let at = u.choose_index(bytes.len() + 1)?;
            let len = u.int_in_range(1..=32)?;
            let junk = u.bytes(len)?.to_vec();
            bytes.splice(at..at, junk);
        }
        // A run of bytes removed, or repeated.
        3 => {
            let at = u.choose_index(bytes.len())?;
            let len = u.int_in_range(1..=64)?.min(bytes.len() - at);
            if u.arbitrary()? {
                bytes.drain(at..at + len);
            } else {
                let copy = bytes[at..at + len].to_vec();
                bytes.splice(at..at, copy);
            }
        }
        // A number swapped for one that breaks code, in the text (or the GLB's JSON).
        _ => {
            return Ok(match kind {
                Kind::Glb => match glb_json(&bytes) {
                    Some((json, bin)) => {
                        let json = swap_number(u, json)?;
                        pelt::export::gltf::glb_container(&json, &bin).unwrap_or(bytes)
                    }
                    None => bytes,
                },
                Kind::Obj | Kind::Gltf => swap_number(u, bytes)?,
            });
        }
    }
    Ok(bytes)
}

/// The JSON and BIN chunks of a GLB, when its header and chunk lengths hold together.
fn glb_json(bytes: &[u8]) -> Option<(Vec<u8>, Vec<u8>)> {
    let word = |at: usize| Some(u32::from_le_bytes(bytes.get(at..at + 4)?.try_into().ok()?) as usize);
    let json_len = word(12)?;
    let json = bytes.get(20..20 + json_len)?.to_vec();
    let bin_at = 20 + json_len;
    let bin = match word(bin_at) {
        Some(len) => bytes.get(bin_at + 8..bin_at + 8 + len)?.to_vec(),
        None => Vec::new(),
    };
    Some((json, bin))
}

/// One number of the text (a run of digits, signs, dots and exponents) replaced by one of
/// [`NUMBERS`].
fn swap_number(u: &mut Unstructured<'_>, bytes: Vec<u8>) -> Arb<Vec<u8>> {
    let starts: Vec<usize> = (0..bytes.len())
        .filter(|&i| bytes[i].is_ascii_digit() && (i == 0 || !is_number_byte(bytes[i - 1])))
        .collect();
    if starts.is_empty() {
        return Ok(bytes);
    }
    let start = starts[u.choose_index(starts.len())?];
    let start = if start > 0 && bytes[start - 1] == b'-' {
        start - 1
    } else {
        start
    };
    let end = (start + 1..bytes.len())
        .find(|&i| !is_number_byte(bytes[i]))
        .unwrap_or(bytes.len());
    let number = NUMBERS[u.choose_index(NUMBERS.len())?].as_bytes();
    let mut out = bytes;
    out.splice(start..end, number.iter().copied());
    Ok(out)
}

fn is_number_byte(b: u8) -> bool {
    b.is_ascii_digit() || matches!(b, b'.' | b'e' | b'E' | b'+' | b'-')
}
