//! Pass (d), the guard hairs (hybrid-fur-volume-and-strands §3): the strands of
//! [`super::FurScene::set_guard_hairs`] as camera-facing tapered ribbons pulled from storage
//! (`strands.wgsl`), interleaved with the shells by height band ([`StrandOrder`]): band `k` of
//! `n` is drawn just before shell `round(k S / n)` of the `S` drawn, holding the strand
//! fragments that stand between the shells around it, and band `n` after every shell.

use super::pipelines::{Model, PassPipelines, PassState, VertexInput};
use super::scene::FurScene;
use super::settings::{RenderSettings, ShellMethod, StrandOrder};

const KAJIYA_KAY: &str = concat!(
    include_str!("common.wgsl"),
    include_str!("lighting.wgsl"),
    include_str!("strands.wgsl"),
    include_str!("strand_kk.wgsl")
);
const PRT: &str = concat!(
    include_str!("common.wgsl"),
    include_str!("prt.wgsl"),
    include_str!("strands.wgsl"),
    include_str!("strand_prt.wgsl")
);

/// Both sides drawn (a ribbon turns to the eye anyway), premultiplied "over"; depth written
/// unless `sorted` ([`StrandOrder::Sorted`]).
pub(super) fn state(model: Model, sorted: bool) -> PassState<'static> {
    PassState {
        label: if sorted { "sorted strands" } else { "strands" },
        source: match model {
            Model::KajiyaKay => KAJIYA_KAY,
            Model::Prt => PRT,
        },
        input: VertexInput::Pulled,
        cull_mode: None,
        depth_write: !sorted,
        blend: Some(wgpu::BlendState::PREMULTIPLIED_ALPHA_BLENDING),
    }
}

/// Smallest share of the strands the strand LOD keeps: past it, the kept strands stay this
/// share and grow translucent instead of ever wider.
pub(super) const MIN_KEPT: f32 = 1.0 / 16.0;

/// Pixels of fur depth per drawn strand segment: a strand a few pixels long is drawn with fewer
/// segments than it has (every `k`-th point), the whole fur depth with at least one.
const SEGMENT_PIXELS: f64 = 4.0;

/// Segments to draw of strands with `segments`, where the fur depth spans `fur_pixels`.
pub(super) fn segments_drawn(segments: u32, fur_pixels: f64) -> u32 {
    let wanted = (fur_pixels / SEGMENT_PIXELS).ceil();
    if wanted.is_nan() {
        return segments;
    }
    (wanted.max(1.0) as u64).min(u64::from(segments)) as u32
}

/// How a frame interleaves strands and shells.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Bands {
    /// Height bands `n`: strand draws `n + 1`, the last after every shell.
    pub count: u32,
    /// Shells drawn.
    pub shells: u32,
    /// Depth not written ([`StrandOrder::Sorted`]).
    pub sorted: bool,
    /// One draw holds every strand fragment, under the shells (stochastic and depth orders,
    /// the marched shells, which one hull draws).
    pub whole: bool,
    /// Coverage kept as a per-pixel random choice ([`StrandOrder::Stochastic`]).
    pub stochastic: bool,
}

impl Bands {
    /// The bands of a frame drawing `shells` shells by `method` (resolved).
    pub fn new(settings: &RenderSettings, shells: u32, method: ShellMethod) -> Bands {
        let (count, sorted) = match settings.strand_order {
            StrandOrder::Stochastic | StrandOrder::Depth => (0, false),
            StrandOrder::Banded(n) => (n, false),
            StrandOrder::Sorted => (shells.max(1), true),
        };
        let whole = method == ShellMethod::Marched || shells == 0 || count == 0;
        Bands {
            count: if whole { 1 } else { count },
            shells,
            sorted: sorted && !whole,
            whole,
            stochastic: settings.strand_order == StrandOrder::Stochastic,
        }
    }

    /// The first shell instance drawn after band `k`'s strands: `round(k S / n)`.
    pub fn shell_start(&self, k: u32) -> u32 {
        if self.whole && k > 0 {
            return self.shells;
        }
        ((u64::from(k) * u64::from(self.shells) * 2 + u64::from(self.count)) / (2 * u64::from(self.count)))
            as u32
    }

    /// Strand draws: `n + 1`, or one when a single band holds everything.
    pub fn draws(&self) -> u32 {
        if self.whole { 1 } else { self.count + 1 }
    }
}

/// Draws band `k` of the scene's strands, `segments` of each (nothing when it has none).
pub(super) fn draw(
    pass: &mut wgpu::RenderPass<'_>,
    pipelines: &PassPipelines,
    scene: &FurScene,
    bands: &Bands,
    k: u32,
    segments: u32,
) {
    let Some(strands) = &scene.strands else {
        return;
    };
    // `set_guard_hairs` checked that every segment of every strand fits in a draw.
    let vertices = 6 * segments * strands.count as u32;
    if vertices == 0 {
        return;
    }
    pass.set_pipeline(if bands.sorted {
        &pipelines.strands_sorted
    } else {
        &pipelines.strands
    });
    pass.set_bind_group(2, &strands.bind_group, &[]);
    pass.draw(0..vertices, k..k + 1);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bands_split_the_shells_evenly_and_the_last_comes_after_them_all() {
        let mut settings = RenderSettings {
            strand_order: StrandOrder::Banded(4),
            ..Default::default()
        };
        let b = Bands::new(&settings, 30, ShellMethod::Instanced);
        let starts: Vec<u32> = (0..=b.count).map(|k| b.shell_start(k)).collect();
        assert_eq!(starts, [0, 8, 15, 23, 30]);
        assert_eq!(b.draws(), 5);
        settings.strand_order = StrandOrder::Sorted;
        let sorted = Bands::new(&settings, 30, ShellMethod::Instanced);
        assert!((0..=30).all(|k| sorted.shell_start(k) == k) && sorted.sorted);
        let marched = Bands::new(&settings, 30, ShellMethod::Marched);
        assert_eq!(
            (marched.draws(), marched.shell_start(0), marched.shell_start(1)),
            (1, 0, 30)
        );
        assert!(!marched.sorted, "one band under the hull writes depth");
        settings.strand_order = StrandOrder::Stochastic;
        let stochastic = Bands::new(&settings, 30, ShellMethod::Instanced);
        assert_eq!((stochastic.draws(), stochastic.shell_start(1)), (1, 30));
    }
}
