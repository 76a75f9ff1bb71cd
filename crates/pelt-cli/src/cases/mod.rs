//! Benchmark cases for `pelt bench` (DESIGN.md §3, "Benchmarks").
//!
//! Each case times its work several times and reports the median, the peak heap growth during one
//! run (when the binary installed `pelt_core::heap::TrackingAllocator`), and, where it has one, an error figure
//! against an independent reference. Speed goals are judged on these figures, never in tests.

use std::time::Instant;

use serde::Serialize;

use pelt_core::error::Result;
use pelt_core::heap::peak_heap;

mod export;
mod gltf;
mod hair;
#[cfg(feature = "metrics")]
mod image;
mod lapped;
mod mesh;
mod prt;
mod reference;
mod render;
#[cfg(feature = "metrics")]
mod strands;
mod stream;
mod volume;

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
    /// The picture's error figures, for `image.*` cases.
    #[serde(flatten)]
    pub image: Option<ImageFigures>,
}

/// What an `image.*` case measures besides its relative MSE (`reference::metrics`).
#[derive(Debug, Clone, Serialize)]
pub struct ImageFigures {
    /// Mean ꟻLIP over the fur's pixels.
    pub flip: f64,
    /// Mean ꟻLIP with both images 4× downsampled.
    pub flip_down4: f64,
    /// Mean fur luminance, preview over reference.
    pub luminance_ratio: f64,
    /// Largest difference of the silhouette's mean coverage per distance bin.
    pub alpha_profile_error: f64,
    /// The silhouette's mean coverage per tenth of a fur depth from the skin's outline, the
    /// preview's then the reference's; `None` where a bin has no pixel.
    pub alpha_profile: [Vec<Option<f64>>; 2],
    /// Fine detail (luminance above about 0.1 cycle per pixel), preview over reference, the
    /// reference's Monte Carlo noise taken out of its detail.
    pub detail_ratio: f64,
    /// The share of the reference's measured detail that was its Monte Carlo noise.
    pub detail_noise_share: f64,
    /// LOD cases: the largest frame-to-frame change of mean luminance along a dolly out to 30×,
    /// over the all-shells image's at the same distance (the pop the LOD adds).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dolly_jump: Option<f64>,
    /// LOD cases: the largest difference from the all-shells image along the dolly.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dolly_drift: Option<f64>,
    /// LOD cases: the largest frame-to-frame change of the all-shells image's mean luminance
    /// along the dolly (the view's own, which the jump leaves out).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dolly_view_change: Option<f64>,
    /// LOD cases: each step of the dolly, `[distance over the framed one, the all-shells
    /// image's mean luminance, the LOD image's]` (where the figures above come from).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dolly_steps: Option<Vec<[f64; 3]>>,
    /// Preview cases: the relative MSE against the reference's volume mode (the volume against
    /// the shells, where the `error` is the strands against the shells).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub volume_error: Option<f64>,
    /// Preview cases: mean fur luminance, preview over the reference's volume mode.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub volume_luminance_ratio: Option<f64>,
}

impl CaseResult {
    /// A result with a timing only (no error figure, no baseline).
    pub(crate) fn timed(name: &str, size: String, (seconds, peak_bytes): (f64, Option<usize>)) -> Self {
        CaseResult {
            name: name.into(),
            size,
            seconds,
            peak_bytes,
            error: None,
            error_metric: None,
            baseline: None,
            speedup: None,
            image: None,
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
    /// Where `image.*` cases write their pictures (reference | preview | ꟻLIP), if anywhere
    /// (only a build with `metrics` has those cases).
    #[cfg_attr(not(feature = "metrics"), allow(dead_code))]
    pub pictures: Option<std::path::PathBuf>,
}

struct Case {
    name: &'static str,
    /// One or more results: a case may time its baseline in the same run.
    run: fn(&BenchOptions) -> Result<Vec<CaseResult>>,
}

const CASES: &[Case] = &[
    Case {
        name: "mesh.build",
        run: mesh::mesh_build,
    },
    Case {
        name: "hair.grow",
        run: hair::hair_grow,
    },
    Case {
        name: "lapped.build",
        run: lapped::lapped_build,
    },
    Case {
        name: "guard.place",
        run: hair::guard_place,
    },
    Case {
        name: "volume.coverage",
        run: volume::coverage_approx,
    },
    Case {
        name: "volume.bake",
        run: volume::volume_bake,
    },
    Case {
        name: "prt.sh.project_equirect",
        run: prt::sh_project_equirect,
    },
    Case {
        name: "export",
        run: export::export_writers,
    },
    Case {
        name: "export.gltf",
        run: gltf::export_gltf,
    },
    Case {
        name: "prt.transfer",
        run: prt::transfer,
    },
    Case {
        name: "prt.bands",
        run: prt::bands,
    },
    Case {
        name: "reference",
        run: reference::reference_render,
    },
    Case {
        name: "render",
        run: render::render_frame,
    },
    #[cfg(feature = "metrics")]
    Case {
        name: "render.frame.hybrid",
        run: strands::strand_cases,
    },
    #[cfg(feature = "metrics")]
    Case {
        name: "image",
        run: image::image_cases,
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
        .filter(|c| runs_group(c.name, prefix))
        .map(|c| (c.run)(options))
        .collect::<Result<Vec<_>>>()?
        .into_iter()
        .flatten()
        .filter(|c| c.name.starts_with(prefix))
        .collect();
    Ok(Report {
        pelt: pelt_core::VERSION,
        threads: pelt_core::threads::thread_count(),
        adapter: adapter_used(),
        cases,
    })
}

/// Whether `--only prefix` runs the group of cases `group`: when its name starts with the
/// prefix, or the prefix names cases inside it ("render.scene" runs the "render" group, whose
/// other cases are then dropped).
pub(super) fn runs_group(group: &str, prefix: &str) -> bool {
    group.starts_with(prefix) || prefix.starts_with(group)
}

/// The GPU adapter the render cases ran on, if any ran.
fn adapter_used() -> Option<String> {
    render::adapter()
}

/// Median seconds of `reps` runs of `work`, after one warm-up run that also measures peak heap.
pub(crate) fn time_median<T>(reps: usize, mut work: impl FnMut() -> T) -> (f64, Option<usize>) {
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

/// Times one run of `work` that also measures its peak heap, for cases too slow to repeat (a
/// reference method that takes minutes); returns the result with the timing.
pub(crate) fn time_once<T>(work: impl FnOnce() -> Result<T>) -> Result<(T, (f64, Option<usize>))> {
    let start = Instant::now();
    let (out, peak) = peak_heap(work);
    let seconds = start.elapsed().as_secs_f64();
    Ok((out?, (seconds, peak)))
}

/// Runs `work` through [`time_median`], keeping the first error instead of timing a failure.
pub(crate) fn time_fallible<T>(
    reps: usize,
    mut work: impl FnMut() -> Result<T>,
) -> Result<(f64, Option<usize>)> {
    let mut failure = None;
    let timing = time_median(reps, || {
        if let Err(e) = work() {
            failure.get_or_insert(e);
        }
    });
    failure.map_or(Ok(timing), Err)
}

/// Runs `work` once and returns its peak heap growth when the tracking allocator is installed.
fn measure_peak<T>(work: &mut impl FnMut() -> T) -> Option<usize> {
    peak_heap(|| std::hint::black_box(work())).1
}

#[cfg(test)]
mod tests {
    use super::runs_group;

    #[test]
    fn only_runs_the_groups_that_can_hold_the_prefixed_cases() {
        assert!(runs_group("render", ""));
        assert!(runs_group("render", "ren"));
        assert!(runs_group("render", "render.scene"));
        assert!(runs_group("volume.bake", "volume"));
        assert!(!runs_group("volume.bake", "volume.coverage"));
        assert!(!runs_group("render", "prt"));
    }
}
