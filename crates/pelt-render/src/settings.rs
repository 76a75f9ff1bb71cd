//! Per-frame render settings: which passes run (Lengyel et al. 2001, §2.3), how many shells —
//! fixed, or chosen by level of detail from the object's projected size (§2.4) — and the
//! background. How long the fur is belongs to the baked asset, not to a frame: the scene holds it
//! ([`super::FurScene::fur_depth`]).

use pelt_core::error::{PeltError, Result};
use pelt_core::params::{Range, Schema};
use serde::Serialize;

/// Largest [`RenderSettings::shells_per_pixel`].
pub const MAX_SHELLS_PER_PIXEL: f32 = 1e3;
/// Largest [`RenderSettings::mesh_error`], pixels.
pub const MAX_MESH_ERROR: f32 = 1e6;

/// How the shells are drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ShellMethod {
    /// Lengyel et al. 2001, §2.3: every shell a copy of the mesh, one instanced draw, each
    /// composited over the last by the blender. Exact per layer; costs a triangle per face and
    /// shell, which a CPU adapter feels most.
    #[default]
    Instanced,
    /// One hull (the outermost shell) whose fragments march down through the layers along the
    /// view ray, the surface taken as flat under each pixel (after the per-pixel rays of
    /// raycast-fur-virtual-planes §3): one mesh's triangles whatever the shell count, one
    /// lighting evaluation per pixel (Banks darkening still per layer), one mip level per
    /// pixel. Drawing all the shells without `lod`, each pixel also reads the LOD chain's
    /// composited groups of layers where the ray crosses a group within about a texel (6 reads
    /// for 32 shells head-on, every layer at the limb). Near the silhouette, where the surface
    /// bends within the ray's run, it differs from the instanced shells most.
    Marched,
    /// The faster method on the adapters measured, for interactive previews: `Marched`, several
    /// times faster than `Instanced` on a CPU adapter and on a GPU alike (`docs/benchmarks.md`,
    /// "Frames on a GPU"); [`crate::Renderer::shell_method`] tells which. The default stays
    /// `Instanced`, the paper's method.
    Auto,
    /// The raycast paper's virtual planes (raycast-fur-virtual-planes §3): one hull whose
    /// fragments trace the view ray through two families of planes standing across the tile's
    /// u and v, each textured with its own slice of the hair volume (the scene's
    /// [`PlaneSlices`](pelt_core::volume::PlaneSlices), [`super::FurScene::set_planes`]), leaning
    /// with the hair, plus the paper's half-z plane (§3.5), then the skin. At most
    /// [`RenderSettings::plane_loop_limit`] planes per pixel; the shell count and LOD do not
    /// apply. The fins cover the silhouette as for the shells (§3.4).
    VirtualPlanes,
}

impl ShellMethod {
    /// The method drawn for this one.
    pub fn resolve(self) -> ShellMethod {
        match self {
            ShellMethod::Auto => ShellMethod::Marched,
            method => method,
        }
    }
}

/// How the guard strands are composited among the shells: the shells are composited inner to
/// outer (the order Lengyel et al. 2001, §2.3 relies on), and a strand fragment belongs among
/// them by its height. A strand thinner than a pixel covers only part of one, which makes it
/// translucent. `docs/benchmarks.md` ("Guard strands in the preview") compares the orders against [`StrandOrder::Sorted`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum StrandOrder {
    /// Stochastic transparency (Enderton et al. 2010): a fragment of a strand that covers a
    /// share `c` of its pixel is drawn opaque with probability `c` (a hash of the pixel and
    /// the strand), so every strand fragment is opaque and one draw under the shells, writing
    /// depth, puts it in its place: right on average, noisy where strands are thin.
    #[default]
    Stochastic,
    /// One draw under the shells, writing depth, the coverage blended as opacity: where a
    /// strand is translucent, the shells behind it are lost and the skin shows through.
    Depth,
    /// `n` height bands (`[1, MAX_STRAND_BANDS]`) interleaved with the shells, the coverage
    /// blended, depth written: band `k` is drawn before shell `round(k S / n)` and the last
    /// after every shell, `n + 1` draws.
    Banded(u32),
    /// A band between every two shells, the coverage blended, no depth written: every strand
    /// fragment lands exactly in the shells' order, a draw per shell. The reference the others
    /// are measured against; the marched shells cannot interleave and draw the strands under
    /// them in one band.
    Sorted,
}

/// Most [`StrandOrder::Banded`] bands.
pub const MAX_STRAND_BANDS: u32 = 256;

/// What to draw and how: per-frame choices only. The fur depth is the scene's
/// ([`super::FurScene::fur_depth`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RenderSettings {
    /// Shells drawn above the skin, `[0, layers − 1]` of the scene's volume; `None` draws all.
    /// Fewer shells than layers pick evenly spaced layers (shell `i` of `s` shows layer
    /// `round(i · (L − 1) / s)` at that layer's height), so the fur keeps its full length. Must
    /// be `None` when `lod` is on.
    pub shell_count: Option<u32>,
    /// Level of detail (Lengyel §2.4): the shell count follows the object's projected size,
    /// between `min_shells` and `max_shells`, drawn from the hair volume's LOD levels (pairs of
    /// shells composited) and cross-faded between the two nearest levels so that nothing pops.
    /// [`super::Renderer::frame_info`] reports the choice.
    pub lod: bool,
    /// LOD: shells per pixel of projected fur depth (the scene's fur depth × the longest painted
    /// length, in pixels at the bounding sphere's centre), `(0, MAX_SHELLS_PER_PIXEL]`. At 1,
    /// shells stand about a pixel apart where the fur is seen edge-on, the fewest that show no
    /// gaps.
    pub shells_per_pixel: f32,
    /// LOD: fewest shells, however small the object (0 allows the skin alone, which then shows
    /// the whole fur composited into it). By default 4, the add-on's too: a group of a quarter
    /// of the layers or fewer is lit at its middle as its layers would be, while the pair and
    /// the single group of the two coarsest levels stray (the benchmark's short-furred patch 5%
    /// dark from 2.4× its framed distance out with 2; within 1.6% with 4).
    pub min_shells: u32,
    /// LOD: most shells, `≥ min_shells` (the volume's `layers − 1` caps it).
    pub max_shells: u32,
    /// How the shells are drawn.
    pub shell_method: ShellMethod,
    /// Geometric level of detail: the most a simplified version of the mesh, drawn by every pass
    /// instead of the full one, may stray from it, in pixels where the object is nearest the
    /// eye (its error bound, which also counts tile UVs, colors and lengths, times the pixels
    /// per object unit there); `[0, MAX_MESH_ERROR]`, 0 always draws the full mesh. The
    /// coarsest level within it is drawn ([`super::FrameInfo::mesh_level`]). Levels are made
    /// with the colors and lengths the scene was uploaded with; after
    /// [`super::FurScene::update_attributes`] changes them, a level that would draw them
    /// further from the full mesh than its bound allows (a bald spot narrower than its
    /// triangles) is no longer drawn, nor any coarser one.
    pub mesh_error: f32,
    /// Draw the fins (Lengyel §2.3, pass b).
    pub fins: bool,
    /// Shadow the directional light by the body: one part of the mesh on the fur of another
    /// (`shadow_map.rs`), as the reference and Blender's renders do. Off, the fur's own model
    /// alone shadows it, as in a runtime that casts no shadows.
    pub body_shadow: bool,
    /// Fin opacity before the silhouette fade, `[0, 1]`.
    pub fin_opacity: f32,
    /// Shell fragments whose opacity is below this write no depth and no color (Lengyel §2.3's
    /// alpha test), `[0, 1]`.
    pub alpha_test: f32,
    /// Background, linear straight RGBA, each `[0, 1]`; the default is transparent black, so
    /// alpha shows coverage.
    pub background: [f32; 4],
    /// Draw the scene's guard hairs ([`super::FurScene::set_guard_hairs`]) as strands over the
    /// shells (hybrid-fur-volume-and-strands §3); without them, or with none set, the frame is
    /// the shells alone.
    pub guard_hairs: bool,
    /// How the strands and shells are composited.
    pub strand_order: StrandOrder,
    /// Strand level of detail: a strand thinner than this many pixels is drawn this wide with
    /// its share of the strands kept (the others dropped, chosen by a per-strand random rank), so
    /// the coverage stays; `[0, MAX_STRAND_PIXELS]`, 0 keeps every strand (a thin one then
    /// drawn a pixel wide, its opacity its coverage).
    pub strand_pixels: f32,
    /// [`ShellMethod::VirtualPlanes`]: the most planes a pixel's ray crosses, the loop limit of
    /// raycast-fur-virtual-planes §4.1 (its main cost), `[1, MAX_PLANE_LOOP_LIMIT]`.
    pub plane_loop_limit: u32,
}

/// Largest [`RenderSettings::plane_loop_limit`].
pub const MAX_PLANE_LOOP_LIMIT: u32 = 256;

/// Largest [`RenderSettings::strand_pixels`].
pub const MAX_STRAND_PIXELS: f32 = 64.0;

impl Default for RenderSettings {
    fn default() -> Self {
        RenderSettings {
            shell_count: None,
            lod: false,
            shells_per_pixel: 1.0,
            min_shells: 4,
            max_shells: 64,
            shell_method: ShellMethod::Instanced,
            mesh_error: 1.0,
            fins: true,
            body_shadow: true,
            fin_opacity: 1.0,
            alpha_test: 1.0 / 255.0,
            background: [0.0; 4],
            guard_hairs: true,
            strand_order: StrandOrder::Stochastic,
            strand_pixels: 1.0,
            plane_loop_limit: 16,
        }
    }
}

impl RenderSettings {
    /// The settings a frame draws with `method` (resolved): the virtual planes trace the whole
    /// fur from one hull, so the shell count and LOD do not apply to them.
    pub(super) fn as_drawn(&self, method: ShellMethod) -> RenderSettings {
        match method {
            ShellMethod::VirtualPlanes => RenderSettings {
                lod: false,
                shell_count: None,
                ..*self
            },
            _ => *self,
        }
    }

    /// Checks every field; returns the number of shells to draw for a volume of `layers` layers
    /// when LOD is off (the count LOD starts from when it is on: all of them).
    pub(super) fn shells_to_draw(&self, layers: u32) -> Result<u32> {
        use ranges::*;
        FIN_OPACITY.check(f64::from(self.fin_opacity))?;
        ALPHA_TEST.check(f64::from(self.alpha_test))?;
        MESH_ERROR.check(f64::from(self.mesh_error))?;
        STRAND_PIXELS.check(f64::from(self.strand_pixels))?;
        if let StrandOrder::Banded(n) = self.strand_order {
            STRAND_BANDS.check(f64::from(n))?;
        }
        PLANE_LOOP_LIMIT.check(f64::from(self.plane_loop_limit))?;
        BACKGROUND.check_each(&self.background.map(f64::from))?;
        SHELLS_PER_PIXEL.check(f64::from(self.shells_per_pixel))?;
        MIN_SHELLS.check(f64::from(self.min_shells))?;
        MAX_SHELLS.check_above(f64::from(self.max_shells), f64::from(self.min_shells))?;
        let most = layers.saturating_sub(1);
        match self.shell_count {
            None => Ok(most),
            Some(_) if self.lod => Err(PeltError::parameter(
                "shell_count",
                "must be None when `lod` is on (LOD chooses the count)",
            )),
            Some(n) if n <= most => Ok(n),
            Some(n) => Err(PeltError::parameter(
                "shell_count",
                format!("must be in [0, {most}] (the scene's volume has {layers} layers), got {n}"),
            )),
        }
    }
}

impl RenderSettings {
    /// The ranges [`Self`]'s numbers are checked against when a frame is drawn, named as Python's
    /// `Preview.render` keywords.
    pub const RANGES: &'static [Range] = {
        use ranges::*;
        &[
            SHELLS_PER_PIXEL,
            MIN_SHELLS,
            MAX_SHELLS,
            MESH_ERROR,
            FIN_OPACITY,
            ALPHA_TEST,
            BACKGROUND,
            STRAND_BANDS,
            STRAND_PIXELS,
            PLANE_LOOP_LIMIT,
        ]
    };

    /// The parameter schema of a frame (`pelt.SCHEMA["render"]`): the defaults as
    /// `Preview.render`'s keywords and the ranges.
    pub fn schema() -> Schema {
        Schema::new::<RenderDefaults>("render", Self::RANGES)
    }
}

/// [`RenderSettings::default`] as `Preview.render`'s keywords spell it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RenderDefaults {
    pub shells: Option<u32>,
    pub lod: bool,
    pub shells_per_pixel: f32,
    pub min_shells: u32,
    pub max_shells: u32,
    /// `instanced`, `marched`, `auto` or `planes`.
    pub shell_method: &'static str,
    pub mesh_error: f32,
    pub fins: bool,
    pub body_shadow: bool,
    pub fin_opacity: f32,
    pub alpha_test: f32,
    pub background: [f32; 4],
    pub guard_hairs: bool,
    /// `stochastic`, `depth`, `banded` or `sorted`.
    pub strand_order: &'static str,
    /// Bands of `strand_order="banded"`.
    pub strand_bands: u32,
    pub strand_pixels: f32,
    pub plane_loop_limit: u32,
}

/// Bands of [`StrandOrder::Banded`] when a front end asks for banding without a count.
pub const DEFAULT_STRAND_BANDS: u32 = 4;

impl Default for RenderDefaults {
    fn default() -> Self {
        let s = RenderSettings::default();
        RenderDefaults {
            shells: s.shell_count,
            lod: s.lod,
            shells_per_pixel: s.shells_per_pixel,
            min_shells: s.min_shells,
            max_shells: s.max_shells,
            shell_method: s.shell_method.name(),
            mesh_error: s.mesh_error,
            fins: s.fins,
            body_shadow: s.body_shadow,
            fin_opacity: s.fin_opacity,
            alpha_test: s.alpha_test,
            background: s.background,
            guard_hairs: s.guard_hairs,
            strand_order: s.strand_order.name(),
            strand_bands: match s.strand_order {
                StrandOrder::Banded(n) => n,
                _ => DEFAULT_STRAND_BANDS,
            },
            strand_pixels: s.strand_pixels,
            plane_loop_limit: s.plane_loop_limit,
        }
    }
}

impl ShellMethod {
    /// The method's name in Python and the command line.
    pub fn name(self) -> &'static str {
        match self {
            ShellMethod::Instanced => "instanced",
            ShellMethod::Marched => "marched",
            ShellMethod::Auto => "auto",
            ShellMethod::VirtualPlanes => "planes",
        }
    }

    /// The method named `name` ([`Self::name`]).
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] naming `shell_method` for an unknown name.
    pub fn from_name(name: &str) -> Result<ShellMethod> {
        [
            ShellMethod::Instanced,
            ShellMethod::Marched,
            ShellMethod::Auto,
            ShellMethod::VirtualPlanes,
        ]
        .into_iter()
        .find(|m| m.name() == name)
        .ok_or_else(|| {
            PeltError::parameter(
                "shell_method",
                format!("must be 'instanced', 'marched', 'auto' or 'planes', got {name:?}"),
            )
        })
    }
}

impl StrandOrder {
    /// The order's name in Python (`Banded` without its count).
    pub fn name(self) -> &'static str {
        match self {
            StrandOrder::Stochastic => "stochastic",
            StrandOrder::Depth => "depth",
            StrandOrder::Banded(_) => "banded",
            StrandOrder::Sorted => "sorted",
        }
    }

    /// The order named `name` ([`Self::name`]), `bands` counting the bands of `banded`.
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] naming `strand_order` for an unknown name.
    pub fn from_name(name: &str, bands: u32) -> Result<StrandOrder> {
        match name {
            "stochastic" => Ok(StrandOrder::Stochastic),
            "depth" => Ok(StrandOrder::Depth),
            "banded" => Ok(StrandOrder::Banded(bands)),
            "sorted" => Ok(StrandOrder::Sorted),
            other => Err(PeltError::parameter(
                "strand_order",
                format!("must be 'stochastic', 'depth', 'banded' or 'sorted', got {other:?}"),
            )),
        }
    }
}

/// The ranges of [`RenderSettings`]' numbers.
mod ranges {
    use super::{MAX_MESH_ERROR, MAX_PLANE_LOOP_LIMIT, MAX_SHELLS_PER_PIXEL, MAX_STRAND_BANDS};
    use super::{MAX_STRAND_PIXELS, Range};

    pub const SHELLS_PER_PIXEL: Range = Range::open_below(
        "shells_per_pixel",
        0.0,
        MAX_SHELLS_PER_PIXEL as f64,
        "shells per pixel of projected fur depth",
    );
    pub const MIN_SHELLS: Range = Range::closed("min_shells", 0.0, u32::MAX as f64, "shells");
    pub const MAX_SHELLS: Range = Range::above_field("max_shells", &MIN_SHELLS, u32::MAX as f64, "shells");
    pub const MESH_ERROR: Range = Range::closed("mesh_error", 0.0, MAX_MESH_ERROR as f64, "pixels");
    pub const FIN_OPACITY: Range = Range::closed("fin_opacity", 0.0, 1.0, "opacity");
    pub const ALPHA_TEST: Range = Range::closed("alpha_test", 0.0, 1.0, "opacity");
    pub const BACKGROUND: Range = Range::closed("background", 0.0, 1.0, "linear straight RGBA");
    pub const STRAND_BANDS: Range =
        Range::closed("strand_bands", 1.0, MAX_STRAND_BANDS as f64, "height bands");
    pub const STRAND_PIXELS: Range = Range::closed("strand_pixels", 0.0, MAX_STRAND_PIXELS as f64, "pixels");
    pub const PLANE_LOOP_LIMIT: Range = Range::closed(
        "plane_loop_limit",
        1.0,
        MAX_PLANE_LOOP_LIMIT as f64,
        "planes per pixel",
    );
}

#[cfg(test)]
mod tests {
    use super::ShellMethod::{Auto, Instanced, Marched, VirtualPlanes};
    use super::{RenderDefaults, RenderSettings, ShellMethod, StrandOrder};
    use pelt_core::error::PeltError;

    /// The defaults with the number `name` set to `x` (a dependent range's field raised along).
    fn with(name: &str, x: f64) -> RenderSettings {
        let mut s = RenderSettings::default();
        let int = x as u32;
        match name {
            "shells_per_pixel" => s.shells_per_pixel = x as f32,
            "min_shells" => (s.min_shells, s.max_shells) = (int, s.max_shells.max(int)),
            "max_shells" => (s.min_shells, s.max_shells) = (0, int),
            "mesh_error" => s.mesh_error = x as f32,
            "fin_opacity" => s.fin_opacity = x as f32,
            "alpha_test" => s.alpha_test = x as f32,
            "background" => s.background = [0.0, 0.0, x as f32, 1.0],
            "strand_bands" => s.strand_order = StrandOrder::Banded(int),
            "strand_pixels" => s.strand_pixels = x as f32,
            "plane_loop_limit" => s.plane_loop_limit = int,
            other => panic!("no field {other}"),
        }
        s
    }

    #[test]
    fn every_range_is_the_one_a_frame_checks() {
        RenderSettings::default().shells_to_draw(16).unwrap();
        for range in RenderSettings::RANGES {
            let integer =
                ["min_shells", "max_shells", "strand_bands", "plane_loop_limit"].contains(&range.name);
            let step = if integer { 1.0 } else { range.max.max(1.0) * 1e-3 };
            let lowest = if range.min_open {
                range.min + step
            } else {
                range.min
            };
            for inside in [lowest, range.max] {
                let result = with(range.name, inside).shells_to_draw(16);
                assert!(result.is_ok(), "{} = {inside}: {result:?}", range.name);
            }
            let below = if range.min_open {
                range.min
            } else {
                range.min - step
            };
            let mut outside = vec![range.max + step];
            if !(integer && below < 0.0) {
                outside.push(below);
            }
            // `u32::MAX + 1` does not fit the field.
            outside.retain(|&x| !integer || x <= f64::from(u32::MAX));
            for x in outside {
                match with(range.name, x).shells_to_draw(16) {
                    Err(PeltError::InvalidParameter { name, .. }) => {
                        assert_eq!(name, range.name, "{} = {x}", range.name)
                    }
                    other => panic!("{} = {x}: {other:?}", range.name),
                }
            }
        }
        let max_below_min = RenderSettings {
            min_shells: 5,
            max_shells: 4,
            ..RenderSettings::default()
        };
        match max_below_min.shells_to_draw(16) {
            Err(PeltError::InvalidParameter { name, .. }) => assert_eq!(name, "max_shells"),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn names_read_back_and_the_defaults_are_the_settings() {
        for m in [Instanced, Marched, Auto, VirtualPlanes] {
            assert_eq!(ShellMethod::from_name(m.name()).unwrap(), m);
        }
        for o in [
            StrandOrder::Stochastic,
            StrandOrder::Depth,
            StrandOrder::Banded(7),
            StrandOrder::Sorted,
        ] {
            assert_eq!(StrandOrder::from_name(o.name(), 7).unwrap(), o);
        }
        assert!(ShellMethod::from_name("flat").is_err());
        let d = RenderDefaults::default();
        let s = RenderSettings::default();
        assert_eq!(
            (d.shells, d.max_shells, d.strand_order),
            (None, s.max_shells, "stochastic")
        );
        // The strands' default order is the one StrandOrder documents as the default.
        assert_eq!(s.strand_order, StrandOrder::default());
    }

    #[test]
    fn auto_marches_and_the_rest_stay() {
        assert_eq!(Auto.resolve(), Marched);
        for method in [Instanced, Marched, VirtualPlanes] {
            assert_eq!(method.resolve(), method);
        }
    }
}
