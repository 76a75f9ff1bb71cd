//! Property-based fuzzing of Pelt's public entry points, on stable Rust.
//!
//! Each target turns seeded random bytes into a structured input through `arbitrary` (numbers
//! drawn mostly from the edges that break code: 0, −0, NaN, ±inf, subnormals, 1e±30, the f32
//! limits, and otherwise from a plausible range), calls the entry point and checks the contract:
//! a result whose every float is finite, or a `PeltError` that names what is wrong (not an
//! internal error). A panic is caught and counted. The cases are independent of each other and of
//! the thread count, so a failure is replayed by its seed and case number.
//!
//! ```text
//! cargo run --release --example fuzz -- TARGET CASES [SEED [FIRST]]    (TARGET: all lists them)
//! ```
//!
//! Prints one JSON line per target (`cases`, `ok`, `refused`, `failures` with the first few) and
//! exits with 1 when anything failed. The `corpus` target (`corpus.rs`) corrupts real files.
//! `scripts/fuzz.py` runs every target in its own process
//! with a time and memory limit, so a hang or an abort is counted too.

use std::cell::Cell;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::Arc;

use arbitrary::{Result as Arb, Unstructured};
use pelt::hair::{CoatParams, HairParams};
use pelt::lapped::{PatchParams, build_patches};
use pelt::mesh::{obj::parse_obj, shapes};
use pelt::pipeline::{BakeParams, Pipeline, TransferChoice};
use pelt::prt::bands::{BandParams, bake_transfer_auto};
use pelt::prt::{Method, Phase, TransferParams, TransferVolume, bake_transfer, sh};
use pelt::volume::{PlaneParams, VolumeParams, bake_volume};
use pelt::{FurMesh, MeshInput, PeltError};

mod corpus;

/// Bytes of randomness per case (more than any target reads).
const CASE_BYTES: usize = 8192;

/// The budget of the fuzzed calls: every case that asks for more is refused, quickly.
const FUZZ_MEMORY_LIMIT: u64 = 256 << 20;

/// Failures reported in full per target.
const SHOWN_FAILURES: usize = 5;

thread_local! {
    /// Odds (1 in this) that a number of the current case is an edge value, 0 for never: a third
    /// of the cases are tame (no edge values, so they reach the work), a third mild (1 in 64),
    /// a third wild (1 in 3, so most exercise the checks).
    static EDGE_ODDS: Cell<u32> = const { Cell::new(0) };
    /// The message of the last refusal, for the report's examples.
    static LAST_REFUSAL: std::cell::RefCell<String> = const { std::cell::RefCell::new(String::new()) };
}

/// Refusals reported as examples per target.
const SHOWN_REFUSALS: usize = 3;

/// What one case ended in.
enum Outcome {
    /// A result, all finite.
    Ok,
    /// A named refusal.
    Refused,
    /// A broken contract, described.
    Failed(String),
}

type Target = fn(&mut Unstructured<'_>) -> Arb<Outcome>;

const TARGETS: &[(&str, Target)] = &[
    ("mesh", mesh_target),
    ("obj", obj_target),
    ("gltf", gltf_target),
    ("patches", patches_target),
    ("volume", volume_target),
    ("transfer", transfer_target),
    ("sh", sh_target),
    ("pipeline", pipeline_target),
    ("corpus", corpus::corpus_target),
];

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (Some(target), Some(cases)) = (args.first(), args.get(1).and_then(|c| c.parse::<u64>().ok())) else {
        eprintln!(
            "usage: fuzz TARGET CASES [SEED]; targets: all, {}",
            names().join(", ")
        );
        std::process::exit(2);
    };
    let seed = args.get(2).and_then(|s| s.parse::<u64>().ok()).unwrap_or(1);
    // Replays from case FIRST (a failure's case number), so one case alone is `CASES = 1`.
    let first = args.get(3).and_then(|s| s.parse::<u64>().ok()).unwrap_or(0);
    // Small on purpose: every case that asks for more is refused by the budget, quickly.
    pelt::memory::set_limit(Some(FUZZ_MEMORY_LIMIT)).expect("a valid limit");
    std::panic::set_hook(Box::new(|_| {}));
    let chosen: Vec<&(&str, Target)> = TARGETS
        .iter()
        .filter(|(n, _)| target == "all" || n == target)
        .collect();
    if chosen.is_empty() {
        eprintln!("unknown target {target:?}; targets: all, {}", names().join(", "));
        std::process::exit(2);
    }
    let mut failed = false;
    for (name, run) in chosen {
        failed |= run_target(name, *run, first..first + cases, seed);
    }
    let _ = std::fs::remove_dir_all(scratch_folder());
    std::process::exit(i32::from(failed));
}

fn names() -> Vec<&'static str> {
    TARGETS.iter().map(|(n, _)| *n).collect()
}

/// Runs `cases` cases of one target; prints its summary line; true when any failed.
fn run_target(name: &str, run: Target, range: std::ops::Range<u64>, seed: u64) -> bool {
    let cases = range.end - range.start;
    let (mut ok, mut refused, mut exhausted, mut failures) = (0u64, 0u64, 0u64, Vec::new());
    let mut refusals: Vec<String> = Vec::new();
    let mut failure_count = 0u64;
    let mut bytes = vec![0u8; CASE_BYTES];
    for case in range {
        fill(&mut bytes, seed, case);
        EDGE_ODDS.set([0, 64, 3][usize::from(bytes[0]) % 3]);
        let mut u = Unstructured::new(&bytes[1..]);
        let outcome = catch_unwind(AssertUnwindSafe(|| run(&mut u))).unwrap_or_else(|payload| {
            let what = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_default();
            Ok(Outcome::Failed(format!("panic: {what}")))
        });
        match outcome {
            Ok(Outcome::Ok) => ok += 1,
            Ok(Outcome::Refused) => {
                refused += 1;
                if refusals.len() < SHOWN_REFUSALS {
                    refusals.push(LAST_REFUSAL.with_borrow(Clone::clone));
                }
            }
            // Ran out of random bytes before the input was complete: nothing was called.
            Err(_) => exhausted += 1,
            Ok(Outcome::Failed(why)) => {
                failure_count += 1;
                if failures.len() < SHOWN_FAILURES {
                    failures.push(format!("case {case}: {why}"));
                }
            }
        }
    }
    let line = serde_json::json!({
        "target": name, "seed": seed, "cases": cases, "ok": ok, "refused": refused,
        "exhausted": exhausted, "failed": failure_count, "failures": failures, "refusals": refusals,
    });
    println!("{line}");
    failure_count > 0
}

/// The bytes of case `case` of `seed` (SplitMix64: independent streams, no state between cases).
fn fill(bytes: &mut [u8], seed: u64, case: u64) {
    let mut state = seed ^ case.wrapping_mul(0x9E37_79B9_7F4A_7C15);
    for chunk in bytes.chunks_mut(8) {
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        chunk.copy_from_slice(&z.to_le_bytes()[..chunk.len()]);
    }
}

/// Whether the next value is an edge value (`rarer` times rarer than the case's odds).
fn edge(u: &mut Unstructured<'_>, rarer: u32) -> Arb<bool> {
    match EDGE_ODDS.get() {
        0 => Ok(false),
        odds => u.ratio(1, odds * rarer),
    }
}

/// A number: one of the edge values that break code, or uniform in `[lo, hi]`.
fn float(u: &mut Unstructured<'_>, lo: f64, hi: f64) -> Arb<f64> {
    const EDGES: [f64; 16] = [
        0.0,
        -0.0,
        1.0,
        -1.0,
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
        1e-30,
        1e30,
        -1e30,
        f32::MAX as f64,
        f32::MIN_POSITIVE as f64,
        1e-45,
        1e-300,
        1e300,
        0.5,
    ];
    Ok(if edge(u, 1)? {
        EDGES[u.choose_index(EDGES.len())?]
    } else {
        lo + (hi - lo) * f64::from(u.int_in_range(0..=1_000_000u32)?) / 1e6
    })
}

fn float32(u: &mut Unstructured<'_>, lo: f64, hi: f64) -> Arb<f32> {
    Ok(float(u, lo, hi)? as f32)
}

/// A count: mostly in `[0, typical]`, sometimes anything up to `u32::MAX`.
fn count(u: &mut Unstructured<'_>, typical: u32) -> Arb<usize> {
    Ok(if edge(u, 2)? {
        if u.arbitrary()? {
            0
        } else {
            u.arbitrary::<u32>()? as usize
        }
    } else {
        u.int_in_range(1..=typical.max(1))? as usize
    })
}

/// Every float of `values` finite, or a description of the first that is not.
fn all_finite<'a>(what: &str, values: impl IntoIterator<Item = &'a f32>) -> Result<(), String> {
    match values.into_iter().position(|v| !v.is_finite()) {
        None => Ok(()),
        Some(i) => Err(format!("{what}[{i}] is not finite")),
    }
}

/// The contract for an error: a named category, never an internal one.
fn judge_error(error: &PeltError) -> Outcome {
    match error {
        PeltError::Internal(m) => Outcome::Failed(format!("internal error: {m}")),
        PeltError::InvalidParameter { name, .. } if name.is_empty() => {
            Outcome::Failed(format!("unnamed parameter: {error}"))
        }
        _ => {
            LAST_REFUSAL.set(error.to_string());
            Outcome::Refused
        }
    }
}

/// `checks` on a result, or [`judge_error`] on an error.
fn judge<T>(result: pelt::Result<T>, checks: impl FnOnce(&T) -> Result<(), String>) -> Outcome {
    match result {
        Ok(value) => match checks(&value) {
            Ok(()) => Outcome::Ok,
            Err(why) => Outcome::Failed(why),
        },
        Err(e) => judge_error(&e),
    }
}

/// Arbitrary positions, triangles and attributes, up to 48 vertices.
fn mesh_target(u: &mut Unstructured<'_>) -> Arb<Outcome> {
    let n = u.int_in_range(0..=48usize)?;
    let scale = float(u, 1e-3, 1e3)?;
    let mut positions: Vec<[f32; 3]> = Vec::with_capacity(n);
    for _ in 0..n {
        let p = [float(u, -1.0, 1.0)?, float(u, -1.0, 1.0)?, float(u, -1.0, 1.0)?];
        positions.push(p.map(|c| (c * scale) as f32));
    }
    let m = u.int_in_range(0..=64usize)?;
    let triangles: Vec<[u32; 3]> = (0..m)
        .map(|_| Ok([index(u, n)?, index(u, n)?, index(u, n)?]))
        .collect::<Arb<_>>()?;
    let rows = |u: &mut Unstructured<'_>, k: usize, lo: f64, hi: f64| -> Arb<Vec<f32>> {
        let extra = usize::from(edge(u, 4)?);
        (0..(n + extra) * k).map(|_| float32(u, lo, hi)).collect()
    };
    let normals = if u.arbitrary()? {
        Some(rows(u, 3, -1.0, 1.0)?)
    } else {
        None
    };
    let color = if u.arbitrary()? {
        Some(rows(u, 4, 0.0, 1.0)?)
    } else {
        None
    };
    let comb = if u.arbitrary()? {
        Some(rows(u, 3, -1.0, 1.0)?)
    } else {
        None
    };
    let length = if u.arbitrary()? {
        Some(rows(u, 1, 0.0, 2.0)?)
    } else {
        None
    };
    let normals3: Option<Vec<[f32; 3]>> = normals.map(|v| v.as_chunks::<3>().0.to_vec());
    let color4: Option<Vec<[f32; 4]>> = color.map(|v| v.as_chunks::<4>().0.to_vec());
    let comb3: Option<Vec<[f32; 3]>> = comb.map(|v| v.as_chunks::<3>().0.to_vec());
    let input = MeshInput {
        normals: normals3.as_deref(),
        color: color4.as_deref(),
        comb: comb3.as_deref(),
        length: length.as_deref(),
        ..MeshInput::new(&positions, &triangles)
    };
    Ok(judge(FurMesh::new(input), |mesh| {
        all_finite("normals", mesh.normals().iter().flatten())?;
        all_finite("tangents", mesh.tangents().iter().flatten())?;
        let area = mesh.stats().surface_area;
        if area.is_finite() {
            Ok(())
        } else {
            Err(format!("surface_area {area}"))
        }
    }))
}

/// A vertex index of a mesh of `n` vertices, now and then one past the end or far beyond.
fn index(u: &mut Unstructured<'_>, n: usize) -> Arb<u32> {
    Ok(if edge(u, 4)? {
        u.int_in_range(n as u32..=u32::MAX)?
    } else {
        u.int_in_range(0..=(n as u32).saturating_sub(1))?
    })
}

/// OBJ text assembled from plausible and broken lines.
fn obj_target(u: &mut Unstructured<'_>) -> Arb<Outcome> {
    let mut text = String::new();
    for _ in 0..u.int_in_range(0..=40)? {
        match u.int_in_range(0..=5)? {
            0..=2 => {
                text += &format!(
                    "v {} {} {}\n",
                    float(u, -2.0, 2.0)?,
                    float(u, -2.0, 2.0)?,
                    float(u, -2.0, 2.0)?
                )
            }
            3 => {
                let k = u.int_in_range(1..=5)?;
                let idx: Vec<String> = (0..k)
                    .map(|_| Ok(u.int_in_range(-12i64..=12)?.to_string()))
                    .collect::<Arb<_>>()?;
                text += &format!("f {}\n", idx.join(" "));
            }
            4 => {
                let len = u.int_in_range(0..=24)?;
                text += &String::from_utf8_lossy(u.bytes(len)?);
            }
            _ => text += "vn 0 0 1\nvt 0.5 0.5\n# comment\ng group\n",
        }
    }
    Ok(judge(parse_obj(&text), |mesh| {
        all_finite("positions", mesh.positions.iter().flatten())
    }))
}

/// A valid GLB of one quad with some of its bytes or JSON numbers changed.
fn gltf_target(u: &mut Unstructured<'_>) -> Arb<Outcome> {
    // The quad as written, unless this case bends a field of it.
    let bend = |u: &mut Unstructured<'_>, good: u32, most: u32| -> Arb<u32> {
        Ok(if edge(u, 1)? {
            u.int_in_range(0..=most)?
        } else {
            good
        })
    };
    let count = bend(u, 4, 6)?;
    let index = bend(u, 0, 3)?;
    let offset = bend(u, 48, 64)?;
    let stride = bend(u, 12, 32)?;
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"buffers":[{{"byteLength":56}}],
"bufferViews":[{{"buffer":0,"byteLength":48,"byteStride":{stride}}},{{"buffer":0,"byteOffset":{offset},"byteLength":8}}],
"accessors":[{{"bufferView":0,"count":{count},"componentType":5126,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}},
{{"bufferView":1,"count":4,"componentType":5123,"type":"SCALAR"}}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":{index}}},"indices":1,"mode":5}}]}}],
"nodes":[{{"mesh":0,"children":[{}]}}],"scenes":[{{"nodes":[0]}}]}}"#,
        if u.ratio(1, 4)? { "0" } else { "" }
    );
    let mut bin: Vec<u8> = [[0f32, 0., 0.], [1., 0., 0.], [0., 1., 0.], [1., 1., 0.]]
        .iter()
        .flatten()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    bin.extend([0u16, 1, 2, 3].iter().flat_map(|v| v.to_le_bytes()));
    let mut file = pelt::export::gltf::glb_container(json.as_bytes(), &bin).expect("a small GLB");
    while edge(u, 1)? {
        let at = u.choose_index(file.len())?;
        file[at] = u.arbitrary()?;
    }
    if edge(u, 2)? {
        file.truncate(u.choose_index(file.len())?);
    }
    let dir = scratch_folder();
    std::fs::create_dir_all(&dir).map_err(|_| arbitrary::Error::IncorrectFormat)?;
    let path = dir.join("case.glb");
    std::fs::write(&path, &file).map_err(|_| arbitrary::Error::IncorrectFormat)?;
    Ok(judge(pelt::mesh::gltf_read::read_gltf(&path), |objects| {
        objects
            .iter()
            .try_for_each(|o| all_finite("positions", o.mesh.positions.iter().flatten()))
    }))
}

/// Where the `gltf` target writes its files (removed when the run ends).
fn scratch_folder() -> std::path::PathBuf {
    std::env::temp_dir().join(format!("pelt-fuzz-gltf-{}", std::process::id()))
}

/// One of the test meshes at a random scale.
fn test_mesh(u: &mut Unstructured<'_>) -> Arb<(FurMesh, f64)> {
    let (positions, triangles) = match u.int_in_range(0..=3)? {
        0 => shapes::uv_sphere(12, 6),
        1 => shapes::torus(12, 6),
        2 => shapes::cube(2),
        _ => shapes::with_zero_area_faces(8, 4),
    };
    let scale = 10f64.powf(f64::from(u.int_in_range(-30i32..=30)?));
    let positions: Vec<[f32; 3]> = positions
        .iter()
        .map(|p| p.map(|c| (f64::from(c) * scale) as f32))
        .collect();
    let mesh = FurMesh::new(MeshInput::new(&positions, &triangles))
        .map_err(|_| arbitrary::Error::IncorrectFormat)?;
    Ok((mesh, scale))
}

fn patch_params(u: &mut Unstructured<'_>, scale: f64) -> Arb<PatchParams> {
    let mut p = PatchParams {
        tile_size: float(u, 0.05, 2.0)? * scale,
        seed: u.arbitrary()?,
        max_alignment_deg: float(u, 0.1, 45.0)?,
        max_face_alignment_deg: float(u, 1.0, 90.0)?,
        stretch_tolerance: float(u, 1.01, 3.0)?,
        max_stretched_fraction: float(u, 0.0, 1.0)?,
        max_stretch: float(u, 3.0, 8.0)?,
        max_patch_faces: count(u, 4096)?,
        ..PatchParams::default()
    };
    p.field.down = [
        float32(u, -1.0, 1.0)?,
        float32(u, -1.0, 1.0)?,
        float32(u, -1.0, 1.0)?,
    ];
    p.field.blend = float(u, 0.0, 1.0)?;
    p.field.comb_weight = float(u, 0.0, 200.0)?;
    Ok(p)
}

/// The lapped patches of a test mesh at any scale with arbitrary parameters.
fn patches_target(u: &mut Unstructured<'_>) -> Arb<Outcome> {
    let (mesh, scale) = test_mesh(u)?;
    let params = patch_params(u, scale)?;
    Ok(judge(build_patches(&mesh, &params), |p| {
        all_finite("uv", p.uv.iter().flatten().flatten())?;
        all_finite("direction", p.direction.iter().flatten())?;
        let q = &p.quality;
        for (name, v) in [
            ("mean_alignment_deg", q.mean_alignment_deg),
            ("coverage", q.coverage),
        ] {
            if !v.is_finite() {
                return Err(format!("quality.{name} = {v}"));
            }
        }
        Ok(())
    }))
}

fn hair_params(u: &mut Unstructured<'_>) -> Arb<HairParams> {
    let coat = |u: &mut Unstructured<'_>| -> Arb<CoatParams> {
        let pair = |u: &mut Unstructured<'_>, hi: f64| -> Arb<[f64; 2]> {
            let mut p = [float(u, 0.0, hi)?, float(u, 0.0, hi)?];
            if !edge(u, 1)? {
                p.sort_by(f64::total_cmp);
            }
            Ok(p)
        };
        Ok(CoatParams {
            length: pair(u, 1.0)?,
            width: pair(u, 0.05)?,
        })
    };
    Ok(HairParams {
        seed: u.arbitrary()?,
        density: count(u, 512)? as u32,
        guard_fraction: float(u, 0.0, 1.0)?,
        undercoat: coat(u)?,
        overcoat: coat(u)?,
        segments: count(u, 12)? as u32,
        taper: float(u, 0.0, 1.0)?,
        curl: float(u, 0.0, 1.0)?,
        helix_radius: float(u, 0.0, 0.1)?,
        helix_frequency: float(u, 0.0, 8.0)?,
        slant: float(u, 0.0, 1.0)?,
        slant_direction: float(u, -4.0, 4.0)?,
        length_jitter: float(u, 0.0, 1.0)?,
        clump_strength: float(u, 0.0, 1.0)?,
        clump_count: count(u, 32)? as u32,
        root_color: [
            float32(u, 0.0, 1.0)?,
            float32(u, 0.0, 1.0)?,
            float32(u, 0.0, 1.0)?,
        ],
        tip_color: [
            float32(u, 0.0, 1.0)?,
            float32(u, 0.0, 1.0)?,
            float32(u, 0.0, 1.0)?,
        ],
        color_jitter: float(u, 0.0, 1.0)?,
    })
}

fn volume_params(u: &mut Unstructured<'_>) -> Arb<VolumeParams> {
    Ok(VolumeParams {
        layers: count(u, 8)?,
        resolution: count(u, 24)?,
        vertical_filter: float(u, 0.0, 2.0)?,
        fin_size: [count(u, 32)?, count(u, 16)?],
        fin_slab: float(u, 0.0, 1.0)?,
        trim: u.arbitrary()?,
        lod: u.arbitrary()?,
        mipmaps: u.arbitrary()?,
        guard_hairs: u.arbitrary()?,
        guard_share: float(u, 0.0, 1.0)?,
        ..VolumeParams::default()
    })
}

/// A hair volume from arbitrary hair and volume parameters.
fn volume_target(u: &mut Unstructured<'_>) -> Arb<Outcome> {
    let (hair, volume) = (hair_params(u)?, volume_params(u)?);
    Ok(judge(bake_volume(&hair, &volume, None), |v| {
        all_finite("coverage", &v.coverage)?;
        let voxels = v.layers * v.resolution * v.resolution;
        if v.coverage.len() != voxels || v.shells.len() != 4 * voxels {
            return Err(format!(
                "array sizes {} / {} for {voxels} voxels",
                v.coverage.len(),
                v.shells.len()
            ));
        }
        Ok(())
    }))
}

fn transfer_params(u: &mut Unstructured<'_>) -> Arb<TransferParams> {
    Ok(TransferParams {
        order: count(u, 9)?,
        directions: 16 + count(u, 64)?,
        sigma: float32(u, 0.0, 4.0)?,
        phase: if u.arbitrary()? {
            Phase::KajiyaKay
        } else {
            Phase::Isotropic
        },
        method: if u.ratio(1, 4)? {
            Method::Brute
        } else {
            Method::Sweep
        },
        brute_step: float32(u, 0.01, 4.0)?,
        sweep_step: float32(u, 0.05, 4.0)?,
        sweep_max_samples: count(u, 32)? as u32,
    })
}

/// The transfer of an arbitrary small density volume.
fn transfer_target(u: &mut Unstructured<'_>) -> Arb<Outcome> {
    let (layers, resolution) = (count(u, 5)?, count(u, 8)?);
    let voxels = layers
        .saturating_mul(resolution)
        .saturating_mul(resolution)
        .min(4096);
    let density: Vec<f32> = (0..voxels).map(|_| float32(u, 0.0, 2.0)).collect::<Arb<_>>()?;
    let tangents: Vec<[f32; 3]> = (0..voxels)
        .map(|_| {
            Ok([
                float32(u, -1.0, 1.0)?,
                float32(u, -1.0, 1.0)?,
                float32(u, -1.0, 1.0)?,
            ])
        })
        .collect::<Arb<_>>()?;
    let volume = TransferVolume {
        layers,
        resolution,
        layer_spacing: float32(u, 0.0, 8.0)?,
        density: &density,
        tangents: if edge(u, 2)? { None } else { Some(&tangents) },
    };
    let params = transfer_params(u)?;
    let finite = |c: &[f32]| all_finite("coefficients", c);
    Ok(if u.arbitrary()? {
        let bands = BandParams {
            tolerance: float(u, 0.0, 0.5)?,
            ..BandParams::default()
        };
        judge(bake_transfer_auto(&volume, &params, &bands, None), |(t, _)| {
            finite(&t.coefficients)
        })
    } else {
        judge(bake_transfer(&volume, &params, None), |t| finite(&t.coefficients))
    })
}

/// Spherical-harmonic projections of arbitrary images and lights.
fn sh_target(u: &mut Unstructured<'_>) -> Arb<Outcome> {
    let order = count(u, 9)?;
    Ok(if u.arbitrary()? {
        let (w, h) = (count(u, 8)?, count(u, 8)?);
        let pixels = w.saturating_mul(h).saturating_mul(3).min(4096);
        let rgb: Vec<f32> = (0..pixels).map(|_| float32(u, 0.0, 10.0)).collect::<Arb<_>>()?;
        judge(sh::project_equirect(order, w, h, &rgb), |c| {
            // The Python layer narrows to f32; the f64 result must at least be finite.
            c.iter()
                .flatten()
                .all(|v| v.is_finite())
                .then_some(())
                .ok_or_else(|| "coefficient not finite".into())
        })
    } else {
        let d = [float(u, -1.0, 1.0)?, float(u, -1.0, 1.0)?, float(u, -1.0, 1.0)?];
        judge(sh::project_cap(order, d, float(u, 0.0, 3.2)?), |c| {
            c.iter()
                .all(|v| v.is_finite())
                .then_some(())
                .ok_or_else(|| "coefficient not finite".into())
        })
    })
}

/// A whole pipeline bake of a test mesh with arbitrary (mostly small) parameters.
fn pipeline_target(u: &mut Unstructured<'_>) -> Arb<Outcome> {
    let (mesh, scale) = test_mesh(u)?;
    let mut params = BakeParams {
        patches: patch_params(u, scale)?,
        hair: hair_params(u)?,
        volume: volume_params(u)?,
        fur_depth: if u.arbitrary()? {
            Some(float(u, 0.01, 1.0)? * scale)
        } else {
            None
        },
        transfer: None,
        planes: if u.arbitrary()? {
            Some(PlaneParams {
                planes: count(u, 8)?,
                size: [count(u, 16)?, count(u, 8)?],
            })
        } else {
            None
        },
    };
    if u.arbitrary()? {
        params.transfer = Some(TransferChoice {
            params: transfer_params(u)?,
            auto: u.arbitrary()?,
            ..TransferChoice::default()
        });
    }
    let mut pipeline = Pipeline::new();
    Ok(judge(pipeline.bake(Arc::new(mesh), &params, None), |asset| {
        all_finite("uv", asset.patches.uv.iter().flatten().flatten())?;
        all_finite("coverage", &asset.volume.coverage)?;
        if let Some(planes) = &asset.planes {
            all_finite("plane tilt", &planes.tilt)?;
        }
        if let Some(guard) = &asset.guard_hairs {
            all_finite("guard hairs", guard.points.iter().flatten())?;
        }
        match &asset.transfer {
            Some(t) => all_finite("coefficients", &t.transfer.coefficients),
            None => Ok(()),
        }
    }))
}
