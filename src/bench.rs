//! Benchmark cases for `pelt bench` (DESIGN.md §3, "Benchmarks").
//!
//! Each case times its work several times and reports the median, the peak heap growth during one
//! run (when the binary installed [`TrackingAllocator`]), and, where it has one, an error figure
//! against an independent reference. Speed goals are judged on these figures, never in tests.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::Instant;

use serde::Serialize;

use crate::error::Result;
use crate::hair::{HairParams, grow_strands};
use crate::mesh::{FurMesh, MeshInput, shapes};
use crate::prt::sh;
use crate::volume::coverage::{CoverageMode, splat_disk};

/// One line of the benchmark table.
#[derive(Debug, Clone, Serialize)]
pub struct CaseResult {
    /// Dotted case name, e.g. `mesh.build`.
    pub name: String,
    /// What was measured, in words (sizes, counts).
    pub size: String,
    /// Median wall-clock seconds.
    pub seconds: f64,
    /// Peak heap growth of one run, bytes; `None` without the tracking allocator.
    pub peak_bytes: Option<usize>,
    /// Error against the reference named in `error_metric`.
    pub error: Option<f64>,
    /// How `error` was measured.
    pub error_metric: Option<String>,
    /// Case this one is compared with.
    pub baseline: Option<String>,
    /// `baseline.seconds / seconds`, measured in the same run.
    pub speedup: Option<f64>,
}

impl CaseResult {
    /// A result with a timing only (no error figure, no baseline).
    fn timed(name: &str, size: String, (seconds, peak_bytes): (f64, Option<usize>)) -> Self {
        CaseResult {
            name: name.into(),
            size,
            seconds,
            peak_bytes,
            error: None,
            error_metric: None,
            baseline: None,
            speedup: None,
        }
    }
}

/// The whole report, as written by `--json`.
#[derive(Debug, Clone, Serialize)]
pub struct Report {
    /// Crate version.
    pub pelt: &'static str,
    /// Threads in Pelt's pool.
    pub threads: usize,
    /// GPU adapter used by render cases, if any ran.
    pub adapter: Option<String>,
    /// One entry per case.
    pub cases: Vec<CaseResult>,
}

/// Options of one benchmark run.
#[derive(Debug, Clone, Default)]
pub struct BenchOptions {
    /// Fewer repetitions and smaller sizes: the whole run under a minute.
    pub quick: bool,
    /// Only cases whose name starts with this.
    pub only: Option<String>,
}

struct Case {
    name: &'static str,
    /// One or more results: a case may time its baseline in the same run.
    run: fn(&BenchOptions) -> Result<Vec<CaseResult>>,
}

const CASES: &[Case] = &[
    Case {
        name: "mesh.build",
        run: mesh_build,
    },
    Case {
        name: "hair.grow",
        run: hair_grow,
    },
    Case {
        name: "volume.coverage",
        run: coverage_approx,
    },
    Case {
        name: "prt.sh.project_equirect",
        run: sh_project_equirect,
    },
];

/// Runs the selected cases in order.
///
/// # Errors
/// Whatever a case's own work returns (none of the current cases fail on valid builds).
pub fn run(options: &BenchOptions) -> Result<Report> {
    let prefix = options.only.as_deref().unwrap_or("");
    let cases = CASES
        .iter()
        .filter(|c| c.name.starts_with(prefix))
        .map(|c| (c.run)(options))
        .collect::<Result<Vec<_>>>()?
        .into_iter()
        .flatten()
        .collect();
    Ok(Report {
        pelt: crate::VERSION,
        threads: crate::threads::thread_count(),
        adapter: None,
        cases,
    })
}

/// Median seconds of `reps` runs of `work`, after one warm-up run that also measures peak heap.
fn time_median<T>(reps: usize, mut work: impl FnMut() -> T) -> (f64, Option<usize>) {
    let peak = measure_peak(&mut work);
    let mut times: Vec<f64> = (0..reps.max(1))
        .map(|_| {
            let start = Instant::now();
            std::hint::black_box(work());
            start.elapsed().as_secs_f64()
        })
        .collect();
    times.sort_by(f64::total_cmp);
    (times[times.len() / 2], peak)
}

/// `mesh.build`: validation, edge map, normals, frames and statistics of a 100k-triangle torus.
fn mesh_build(options: &BenchOptions) -> Result<Vec<CaseResult>> {
    let (positions, triangles) = shapes::torus(224, 224);
    let reps = if options.quick { 7 } else { 31 };
    let timing = time_fallible(reps, || FurMesh::new(MeshInput::new(&positions, &triangles)))?;
    let size = format!("{} triangles, {} vertices", triangles.len(), positions.len());
    Ok(vec![CaseResult::timed("mesh.build", size, timing)])
}

/// Runs `work` through [`time_median`], keeping the first error instead of timing a failure.
fn time_fallible<T>(reps: usize, mut work: impl FnMut() -> Result<T>) -> Result<(f64, Option<usize>)> {
    let mut failure = None;
    let timing = time_median(reps, || {
        if let Err(e) = work() {
            failure.get_or_insert(e);
        }
    });
    failure.map_or(Ok(timing), Err)
}

/// `hair.grow`: one tile of strands with clumping and a helix.
fn hair_grow(options: &BenchOptions) -> Result<Vec<CaseResult>> {
    let params = HairParams {
        density: if options.quick { 65_536 } else { 262_144 },
        clump_count: 64,
        clump_strength: 0.4,
        helix_radius: 0.002,
        helix_frequency: 2.0,
        ..HairParams::default()
    };
    let timing = time_fallible(if options.quick { 5 } else { 15 }, || grow_strands(&params))?;
    let size = format!(
        "{} strands x {} segments, {} clumps",
        params.density, params.segments, params.clump_count
    );
    Ok(vec![CaseResult::timed("hair.grow", size, timing)])
}

/// `volume.coverage.approx`: the root cross-sections of the default strands splatted into one
/// 128² layer with the paper's chord/wedge approximation, against the exact area in the same run.
fn coverage_approx(options: &BenchOptions) -> Result<Vec<CaseResult>> {
    const RES: usize = 128;
    let strands = grow_strands(&HairParams::default())?;
    let splat_all = |mode: CoverageMode| -> Result<Vec<f32>> {
        let mut grid = vec![0.0f32; RES * RES];
        for s in &strands {
            splat_disk(&mut grid, RES, s.root[0], s.root[1], s.radii[0], mode)?;
        }
        Ok(grid)
    };
    let exact = splat_all(CoverageMode::Exact)?;
    let approx = splat_all(CoverageMode::Approx)?;
    let error = exact
        .iter()
        .zip(&approx)
        .map(|(a, b)| f64::from((a - b).abs()))
        .fold(0.0, f64::max);
    let reps = if options.quick { 7 } else { 31 };
    let exact_timing = time_fallible(reps, || splat_all(CoverageMode::Exact))?;
    let approx_timing = time_fallible(reps, || splat_all(CoverageMode::Approx))?;
    let size = format!("{} disks into {RES}x{RES}", strands.len());
    Ok(vec![
        CaseResult::timed("volume.coverage.exact", size.clone(), exact_timing),
        CaseResult {
            error: Some(error),
            error_metric: Some("max absolute texel coverage difference vs exact".into()),
            baseline: Some("volume.coverage.exact".into()),
            speedup: Some(exact_timing.0 / approx_timing.0),
            ..CaseResult::timed("volume.coverage.approx", size, approx_timing)
        },
    ])
}

/// `prt.sh.project_equirect`: an HDR environment (a sky gradient and a sun disk) to order-8 SH.
fn sh_project_equirect(options: &BenchOptions) -> Result<Vec<CaseResult>> {
    let (width, height) = if options.quick { (512, 256) } else { (2048, 1024) };
    let rgb: Vec<f32> = (0..width * height)
        .flat_map(|i| {
            let (x, y) = (
                (i % width) as f32 / width as f32,
                (i / width) as f32 / height as f32,
            );
            let sun = if (x - 0.3).hypot(y - 0.25) < 0.01 {
                50.0
            } else {
                0.0
            };
            [
                0.2 + 0.8 * (1.0 - y) + sun,
                0.3 + 0.7 * (1.0 - y) + sun,
                1.0 - 0.5 * y + sun,
            ]
        })
        .collect();
    let timing = time_fallible(if options.quick { 5 } else { 11 }, || {
        sh::project_equirect(sh::MAX_ORDER, width, height, &rgb)
    })?;
    let size = format!("{width}x{height} RGB, order {}", sh::MAX_ORDER);
    Ok(vec![CaseResult::timed("prt.sh.project_equirect", size, timing)])
}

static TRACKING: AtomicBool = AtomicBool::new(false);
static CURRENT: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

/// A global allocator that counts live heap bytes, so cases can report their peak. The `pelt`
/// binary installs it; the library and the Python module do not.
pub struct TrackingAllocator;

// SAFETY: forwards every call to the system allocator unchanged; only counts sizes.
unsafe impl GlobalAlloc for TrackingAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // SAFETY: same contract as the caller's.
        let ptr = unsafe { System.alloc(layout) };
        if !ptr.is_null() {
            let now = CURRENT.fetch_add(layout.size(), Ordering::Relaxed) + layout.size();
            PEAK.fetch_max(now, Ordering::Relaxed);
        }
        ptr
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: same contract as the caller's.
        unsafe { System.dealloc(ptr, layout) };
        CURRENT.fetch_sub(layout.size(), Ordering::Relaxed);
    }
}

impl TrackingAllocator {
    /// Tells [`run`] that the allocator is installed (call once from `main`).
    pub fn enable() {
        TRACKING.store(true, Ordering::Relaxed);
    }
}

/// Runs `work` once and returns its peak heap growth when the tracking allocator is installed.
fn measure_peak<T>(work: &mut impl FnMut() -> T) -> Option<usize> {
    if !TRACKING.load(Ordering::Relaxed) {
        std::hint::black_box(work());
        return None;
    }
    let base = CURRENT.load(Ordering::Relaxed);
    PEAK.store(base, Ordering::Relaxed);
    std::hint::black_box(work());
    Some(PEAK.load(Ordering::Relaxed).saturating_sub(base))
}
