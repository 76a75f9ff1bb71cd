//! Per-frame render settings: which passes run (Lengyel et al. 2001, §2.3), how many shells —
//! fixed, or chosen by level of detail from the object's projected size (§2.4) — and the
//! background. How long the fur is belongs to the baked asset, not to a frame: the scene holds it
//! ([`super::FurScene::fur_depth`]).

use pelt_core::error::{Num, PeltError, Result};

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
    /// `Marched` on a CPU adapter, where it is several times faster, `Instanced` on a GPU
    /// ([`crate::Renderer::shell_method`] tells which): for interactive previews. The
    /// default stays `Instanced`, so that the same settings draw the same way on every adapter.
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
    /// The method drawn for this one on an adapter that is (`cpu`) or is not a CPU.
    pub fn resolve(self, cpu: bool) -> ShellMethod {
        match self {
            ShellMethod::Auto if cpu => ShellMethod::Marched,
            ShellMethod::Auto => ShellMethod::Instanced,
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
    /// the whole fur composited into it).
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
            min_shells: 2,
            max_shells: 64,
            shell_method: ShellMethod::Instanced,
            mesh_error: 1.0,
            fins: true,
            fin_opacity: 1.0,
            alpha_test: 1.0 / 255.0,
            background: [0.0; 4],
            guard_hairs: true,
            strand_order: StrandOrder::Depth,
            strand_pixels: 1.0,
            plane_loop_limit: 16,
        }
    }
}

/// `value` finite and in `[0, hi]`, else an error naming `name`.
pub(super) fn check(name: &str, value: f32, hi: f32) -> Result<()> {
    if value.is_finite() && (0.0..=hi).contains(&value) {
        Ok(())
    } else {
        Err(PeltError::parameter(
            name,
            format!("must be in [0, {hi}], got {}", Num(f64::from(value))),
        ))
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
        check("settings.fin_opacity", self.fin_opacity, 1.0)?;
        check("settings.alpha_test", self.alpha_test, 1.0)?;
        check("settings.mesh_error", self.mesh_error, MAX_MESH_ERROR)?;
        check("settings.strand_pixels", self.strand_pixels, MAX_STRAND_PIXELS)?;
        if let StrandOrder::Banded(n) = self.strand_order
            && !(1..=MAX_STRAND_BANDS).contains(&n)
        {
            return Err(PeltError::parameter(
                "settings.strand_order",
                format!("Banded must have [1, {MAX_STRAND_BANDS}] bands, got {n}"),
            ));
        }
        pelt_core::error::check_range(
            "settings.plane_loop_limit",
            f64::from(self.plane_loop_limit),
            1.0,
            f64::from(MAX_PLANE_LOOP_LIMIT),
        )?;
        for (i, &c) in self.background.iter().enumerate() {
            check(&format!("settings.background[{i}]"), c, 1.0)?;
        }
        if !(self.shells_per_pixel.is_finite()
            && self.shells_per_pixel > 0.0
            && self.shells_per_pixel <= MAX_SHELLS_PER_PIXEL)
        {
            return Err(PeltError::parameter(
                "settings.shells_per_pixel",
                format!(
                    "must be in (0, {MAX_SHELLS_PER_PIXEL}], got {}",
                    self.shells_per_pixel
                ),
            ));
        }
        if self.min_shells > self.max_shells {
            return Err(PeltError::parameter(
                "settings.min_shells",
                format!(
                    "must not exceed settings.max_shells ({}), got {}",
                    self.max_shells, self.min_shells
                ),
            ));
        }
        let most = layers.saturating_sub(1);
        match self.shell_count {
            None => Ok(most),
            Some(_) if self.lod => Err(PeltError::parameter(
                "settings.shell_count",
                "must be None when settings.lod is on (LOD chooses the count)",
            )),
            Some(n) if n <= most => Ok(n),
            Some(n) => Err(PeltError::parameter(
                "settings.shell_count",
                format!("must be in [0, {most}] (the scene's volume has {layers} layers), got {n}"),
            )),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::ShellMethod::{Auto, Instanced, Marched, VirtualPlanes};

    #[test]
    fn auto_marches_on_a_cpu_and_instances_on_a_gpu_and_the_rest_stay() {
        assert_eq!(Auto.resolve(true), Marched);
        assert_eq!(Auto.resolve(false), Instanced);
        for cpu in [true, false] {
            assert_eq!(Instanced.resolve(cpu), Instanced);
            assert_eq!(Marched.resolve(cpu), Marched);
            assert_eq!(VirtualPlanes.resolve(cpu), VirtualPlanes);
        }
    }
}
