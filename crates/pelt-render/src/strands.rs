//! Pass (d), the guard hairs (hybrid-fur-volume-and-strands §3): the strands of
//! [`super::FurScene::set_guard_hairs`] as camera-facing tapered ribbons pulled from storage
//! (`strands.wgsl`), interleaved with the shells by height band ([`StrandOrder`]): band `k` of
//! `n` is drawn just before shell `round(k S / n)` of the `S` drawn, holding the strand
//! fragments that stand between the shells around it, and band `n` after every shell.

use super::guard_strands::GpuStrand;
use super::pass::{Model, PassState, VertexInput, build_pipeline};
use super::scene::FurScene;
use super::settings::{RenderSettings, ShellMethod, StrandOrder};
use super::shaders::PassShader;
use pelt_core::error::Result;

/// The pass's shader, one source for both lighting models.
pub(super) static SHADER: PassShader = PassShader::new("strands.wgsl", include_str!("strands.wgsl"));

/// One triangle strip, both sides drawn (a ribbon turns to the eye anyway),
/// premultiplied "over"; depth written unless `sorted` ([`StrandOrder::Sorted`]).
fn state(model: Model, sorted: bool) -> Result<PassState<'static>> {
    Ok(PassState {
        label: if sorted { "sorted strands" } else { "strands" },
        module: SHADER.module(model)?,
        input: VertexInput::Pulled,
        topology: wgpu::PrimitiveTopology::TriangleStrip,
        cull_mode: None,
        depth_write: !sorted,
        blend: Some(wgpu::BlendState::PREMULTIPLIED_ALPHA_BLENDING),
    })
}

/// Smallest share of the strands the strand LOD keeps: past it, the kept strands stay this
/// share and grow translucent instead of ever wider.
pub(super) const MIN_KEPT: f32 = 1.0 / 16.0;

/// How many of `strands` (as uploaded, in ascending LOD rank) the strand LOD may keep in a frame where their thickest root (`radius`) is at most `pixels_per_unit` pixels per
/// object unit: the vertex shader keeps a strand when its rank is below its width over
/// `strand_pixels`, so the strands past that with the thickest root nearest the eye are left
/// out of the draw (a quarter more kept, for the shader's own measure).
pub(super) fn kept_strands(
    strands: &[GpuStrand],
    radius: f32,
    pixels_per_unit: Option<f64>,
    strand_pixels: f32,
) -> u32 {
    let keep = match pixels_per_unit {
        Some(ppu) if strand_pixels > 0.0 => {
            let across = 2.0 * f64::from(radius) * ppu / f64::from(strand_pixels);
            1.25 * across.max(f64::from(MIN_KEPT))
        }
        _ => f64::INFINITY,
    };
    strands.partition_point(|s| f64::from(s.root_color[3]) < keep) as u32
}

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
    /// The bands of a frame drawing `shells` shells by `method` (resolved), with `strands`
    /// drawn or none (then one band: the shells in one draw).
    pub fn new(settings: &RenderSettings, shells: u32, method: ShellMethod, strands: bool) -> Bands {
        let (count, sorted) = match settings.strand_order {
            StrandOrder::Stochastic | StrandOrder::Depth => (0, false),
            StrandOrder::Banded(n) => (n, false),
            StrandOrder::Sorted => (shells.max(1), true),
        };
        let whole = !strands
            || matches!(method, ShellMethod::Marched | ShellMethod::VirtualPlanes)
            || shells == 0
            || count == 0;
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

/// The strands' pipelines for one lighting model and target: writing depth, and not
/// ([`StrandOrder::Sorted`]).
pub(super) struct StrandsPass {
    depth_writing: wgpu::RenderPipeline,
    sorted: wgpu::RenderPipeline,
}

impl StrandsPass {
    /// `layout` holds the strands' group 2.
    pub(super) fn new(
        device: &wgpu::Device,
        layout: &wgpu::PipelineLayout,
        model: Model,
        format: wgpu::TextureFormat,
    ) -> Result<Self> {
        Ok(StrandsPass {
            depth_writing: build_pipeline(device, layout, &state(model, false)?, format),
            sorted: build_pipeline(device, layout, &state(model, true)?, format),
        })
    }

    /// The first `strands` of the scene's (those the strand LOD may keep, [`kept_strands`]),
    /// band `k`, `segments` of each; nothing when there are none.
    pub(super) fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        scene: &FurScene,
        bands: &Bands,
        k: u32,
        (strands, segments): (u32, u32),
    ) {
        let Some(guard) = &scene.strands else {
            return;
        };
        if strands == 0 || segments == 0 {
            return;
        }
        pass.set_pipeline(if bands.sorted {
            &self.sorted
        } else {
            &self.depth_writing
        });
        pass.set_bind_group(2, &guard.bind_group, &[]);
        // Each strand's block of the strip (`strands.wgsl`); at most 2^20 strands of 64 segments.
        pass.draw(0..strands * (2 * segments + 4), k..k + 1);
    }
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
        let b = Bands::new(&settings, 30, ShellMethod::Instanced, true);
        let starts: Vec<u32> = (0..=b.count).map(|k| b.shell_start(k)).collect();
        assert_eq!(starts, [0, 8, 15, 23, 30]);
        assert_eq!(b.draws(), 5);
        settings.strand_order = StrandOrder::Sorted;
        let sorted = Bands::new(&settings, 30, ShellMethod::Instanced, true);
        let none = Bands::new(&settings, 30, ShellMethod::Instanced, false);
        assert_eq!((none.draws(), none.shell_start(1), none.sorted), (1, 30, false));
        assert!((0..=30).all(|k| sorted.shell_start(k) == k) && sorted.sorted);
        let marched = Bands::new(&settings, 30, ShellMethod::Marched, true);
        assert_eq!(
            (marched.draws(), marched.shell_start(0), marched.shell_start(1)),
            (1, 0, 30)
        );
        assert!(!marched.sorted, "one band under the hull writes depth");
        settings.strand_order = StrandOrder::Stochastic;
        let stochastic = Bands::new(&settings, 30, ShellMethod::Instanced, true);
        assert_eq!((stochastic.draws(), stochastic.shell_start(1)), (1, 30));
    }

    #[test]
    fn the_draw_keeps_the_strands_whose_rank_the_lod_may_keep() {
        let ranks = [0.01, 0.05, 0.1, 0.2, 0.4, 0.8].map(|rank| GpuStrand {
            root_color: [0.0, 0.0, 0.0, rank],
            ..bytemuck::Zeroable::zeroed()
        });
        // Roots 0.04 px across at most: the floor 1/16, a quarter more, keeps ranks below 0.078.
        assert_eq!(kept_strands(&ranks, 0.2, Some(0.1), 1.0), 2);
        // 0.24 px: ranks below 0.3.
        assert_eq!(kept_strands(&ranks, 0.6, Some(0.2), 1.0), 4);
        assert_eq!(kept_strands(&ranks, 0.6, Some(0.2), 0.0), 6, "no LOD: all");
        assert_eq!(kept_strands(&ranks, 0.6, None, 1.0), 6, "no measure: all");
        assert_eq!(kept_strands(&ranks, 10.0, Some(1.0), 1.0), 6);
    }
}
