//! Procedural hair strands in one toroidal tile of the hair volume.
//!
//! Lengyel et al. 2001, §2.2 ("Texture preprocessing") grow the geometric hair inside a small
//! rectangular volume with toroidal symmetry along the two skin axes, so that the shell textures
//! sampled from it tile. This module builds that geometry with the hair model of the PRT shell-fur
//! paper (`prt-shell-fur`, §2.1 "Creating Fur"): each hair gets a random base width that falls off
//! linearly towards the tip, and curls along a parabola in a random direction. On top of that it
//! adds an undercoat and an overcoat of guard hairs, a helix, a slant of the growth direction,
//! clumping and per-strand color jitter, which the paper's "varying the parameters" alludes to.
//!
//! Units: the tile is the unit square laterally and height 1 is the fur depth. Roots lie in
//! `[0, 1)²`; a strand that leans over a tile edge keeps unwrapped coordinates and consumers wrap
//! them modulo 1. Everything derives from [`HairParams::seed`] through a small counter-based
//! generator (one independent stream per strand), so the strands are bit-identical for any thread
//! count.

use std::f64::consts::TAU;

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::error::Result;
use crate::rng::Rng;
use crate::threads::pool;

/// Most hairs per tile: 1024², four times a 512² shell texture's texel count.
pub const MAX_DENSITY: u32 = 1 << 20;
/// Most clump centres per tile (the nearest centre is found by a linear scan).
pub const MAX_CLUMPS: u32 = 256;
/// Most polyline segments per strand.
pub const MAX_SEGMENTS: u32 = 64;
/// Largest base width of a hair, tile units (a tenth of the tile).
pub const MAX_WIDTH: f64 = 0.1;
/// Largest helix radius, tile units.
pub const MAX_HELIX_RADIUS: f64 = 0.1;
/// Most helix turns over a strand's height.
pub const MAX_HELIX_FREQUENCY: f64 = 32.0;
/// Largest slant, radians (80°): beyond it a strand would lie almost flat in the tile.
pub const MAX_SLANT: f64 = 1.396_263_401_595_463_6;

/// Parameters of one coat (undercoat or overcoat).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CoatParams {
    /// `[min, max]` height reached by the tip, in fur depths; each in `[0, 1]`, `min <= max`.
    pub length: [f64; 2],
    /// `[min, max]` base width (diameter) in tile units; each in `[0, MAX_WIDTH]`, `min <= max`.
    pub width: [f64; 2],
}

/// Everything that shapes the hair of one tile. All ranges are closed intervals.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct HairParams {
    /// Seed of every random choice; any value.
    pub seed: u64,
    /// Hairs per tile, `[0, MAX_DENSITY]`.
    pub density: u32,
    /// Share of the hairs that are guard hairs (overcoat), `[0, 1]`.
    pub guard_fraction: f64,
    /// The dense, short hairs.
    pub undercoat: CoatParams,
    /// The sparse, long guard hairs.
    pub overcoat: CoatParams,
    /// Polyline segments per strand, `[1, MAX_SEGMENTS]`.
    pub segments: u32,
    /// Tip width / base width, `[0, 1]`; the width falls off linearly in between (§2.1).
    pub taper: f64,
    /// Parabolic curl: lateral offset of the tip as a share of the strand's height, `[0, 1]`.
    pub curl: f64,
    /// Radius of the helix around the growth path, tile units, `[0, MAX_HELIX_RADIUS]`.
    pub helix_radius: f64,
    /// Helix turns over a strand's height, `[0, MAX_HELIX_FREQUENCY]`.
    pub helix_frequency: f64,
    /// Tilt of the growth direction away from the normal, radians, `[0, MAX_SLANT]`.
    pub slant: f64,
    /// Direction of the tilt in the tile plane, radians from +x, `[-2π, 2π]`.
    pub slant_direction: f64,
    /// Random shortening of each strand: its height is multiplied by `1 - length_jitter·u`, `u`
    /// uniform in `[0, 1)`; `[0, 1]`.
    pub length_jitter: f64,
    /// How far tips are pulled towards their clump centre (1 = onto it), `[0, 1]`.
    pub clump_strength: f64,
    /// Clump centres per tile, `[0, MAX_CLUMPS]`; 0 disables clumping.
    pub clump_count: u32,
    /// Linear color at the root, each component in `[0, 1]`.
    pub root_color: [f32; 3],
    /// Linear color at the tip, each component in `[0, 1]`.
    pub tip_color: [f32; 3],
    /// Random darkening of each strand: its colors are multiplied by `1 - color_jitter·u`; `[0, 1]`.
    pub color_jitter: f64,
}

impl Default for HairParams {
    /// A short, dense pelt: 128² hairs, one in twenty a guard hair, widths below one texel of a
    /// 128² shell texture as the paper's coverage approximation assumes (§2.1).
    fn default() -> Self {
        HairParams {
            seed: 1,
            density: 16384,
            guard_fraction: 0.05,
            undercoat: CoatParams {
                length: [0.55, 0.8],
                width: [0.004, 0.006],
            },
            overcoat: CoatParams {
                length: [0.85, 1.0],
                width: [0.006, 0.0075],
            },
            segments: 16,
            taper: 0.2,
            curl: 0.1,
            helix_radius: 0.0,
            helix_frequency: 0.0,
            slant: 0.2,
            slant_direction: 0.0,
            length_jitter: 0.1,
            clump_strength: 0.0,
            clump_count: 0,
            root_color: [0.12, 0.08, 0.05],
            tip_color: [0.45, 0.32, 0.2],
            color_jitter: 0.15,
        }
    }
}

/// The ranges of [`HairParams`]' numbers (`crate::params`).
mod ranges {
    use super::*;
    use crate::params::Range;

    pub const DENSITY: Range = Range::closed("density", 0.0, MAX_DENSITY as f64, "hairs per tile");
    pub const GUARD_FRACTION: Range = Range::closed("guard_fraction", 0.0, 1.0, "share of the hairs");
    pub const UNDERCOAT_LENGTH: Range = Range::closed("undercoat.length", 0.0, 1.0, "fur depths");
    pub const UNDERCOAT_WIDTH: Range = Range::closed("undercoat.width", 0.0, MAX_WIDTH, "tile widths");
    pub const OVERCOAT_LENGTH: Range = Range::closed("overcoat.length", 0.0, 1.0, "fur depths");
    pub const OVERCOAT_WIDTH: Range = Range::closed("overcoat.width", 0.0, MAX_WIDTH, "tile widths");
    pub const SEGMENTS: Range = Range::closed("segments", 1.0, MAX_SEGMENTS as f64, "segments per strand");
    pub const TAPER: Range = Range::closed("taper", 0.0, 1.0, "tip width over base width");
    pub const CURL: Range = Range::closed("curl", 0.0, 1.0, "share of the strand's height");
    pub const HELIX_RADIUS: Range = Range::closed("helix_radius", 0.0, MAX_HELIX_RADIUS, "tile widths");
    pub const HELIX_FREQUENCY: Range =
        Range::closed("helix_frequency", 0.0, MAX_HELIX_FREQUENCY, "turns per strand");
    pub const SLANT: Range = Range::closed("slant", 0.0, MAX_SLANT, "radians");
    pub const SLANT_DIRECTION: Range = Range::closed("slant_direction", -TAU, TAU, "radians");
    pub const LENGTH_JITTER: Range = Range::closed("length_jitter", 0.0, 1.0, "share of the height");
    pub const CLUMP_STRENGTH: Range = Range::closed("clump_strength", 0.0, 1.0, "share of the way");
    pub const CLUMP_COUNT: Range = Range::closed("clump_count", 0.0, MAX_CLUMPS as f64, "clumps per tile");
    pub const ROOT_COLOR: Range = Range::closed("root_color", 0.0, 1.0, "linear RGB");
    pub const TIP_COLOR: Range = Range::closed("tip_color", 0.0, 1.0, "linear RGB");
    pub const COLOR_JITTER: Range = Range::closed("color_jitter", 0.0, 1.0, "share of the color");
}

impl HairParams {
    /// Every number's range, as [`HairParams::validate`] checks it.
    pub const RANGES: &'static [crate::params::Range] = {
        use ranges::*;
        &[
            DENSITY,
            GUARD_FRACTION,
            UNDERCOAT_LENGTH,
            UNDERCOAT_WIDTH,
            OVERCOAT_LENGTH,
            OVERCOAT_WIDTH,
            SEGMENTS,
            TAPER,
            CURL,
            HELIX_RADIUS,
            HELIX_FREQUENCY,
            SLANT,
            SLANT_DIRECTION,
            LENGTH_JITTER,
            CLUMP_STRENGTH,
            CLUMP_COUNT,
            ROOT_COLOR,
            TIP_COLOR,
            COLOR_JITTER,
        ]
    };

    /// Checks every field against its documented range.
    ///
    /// # Errors
    /// [`crate::PeltError::InvalidParameter`] naming the first field out of range (NaN is out of every
    /// range); coat fields are named `undercoat.length`, `overcoat.width` and so on.
    pub fn validate(&self) -> Result<()> {
        use ranges::*;
        DENSITY.check(f64::from(self.density))?;
        GUARD_FRACTION.check(self.guard_fraction)?;
        UNDERCOAT_LENGTH.check_pair(self.undercoat.length)?;
        UNDERCOAT_WIDTH.check_pair(self.undercoat.width)?;
        OVERCOAT_LENGTH.check_pair(self.overcoat.length)?;
        OVERCOAT_WIDTH.check_pair(self.overcoat.width)?;
        SEGMENTS.check(f64::from(self.segments))?;
        TAPER.check(self.taper)?;
        CURL.check(self.curl)?;
        HELIX_RADIUS.check(self.helix_radius)?;
        HELIX_FREQUENCY.check(self.helix_frequency)?;
        SLANT.check(self.slant)?;
        SLANT_DIRECTION.check(self.slant_direction)?;
        LENGTH_JITTER.check(self.length_jitter)?;
        CLUMP_STRENGTH.check(self.clump_strength)?;
        CLUMP_COUNT.check(f64::from(self.clump_count))?;
        ROOT_COLOR.check_each(&self.root_color.map(f64::from))?;
        TIP_COLOR.check_each(&self.tip_color.map(f64::from))?;
        COLOR_JITTER.check(self.color_jitter)
    }

    /// The coat grown over a mesh with painted colors (`pelt_color`), which multiply the texels:
    /// the colors divided, per channel, by the brighter of root and tip, so the painted color
    /// shows as painted where the hair is brightest and the coat keeps only its shading (the
    /// root's share of the tip, the jitter). A channel black at both ends becomes white. A mesh
    /// without painted colors (`painted` false) gets the coat as set.
    #[must_use]
    pub fn under_paint(&self, painted: bool) -> HairParams {
        if !painted {
            return self.clone();
        }
        let brightest: [f32; 3] = std::array::from_fn(|c| self.root_color[c].max(self.tip_color[c]));
        let share = |color: [f32; 3]| {
            std::array::from_fn(|c| {
                if brightest[c] > 0.0 {
                    color[c] / brightest[c]
                } else {
                    1.0
                }
            })
        };
        HairParams {
            root_color: share(self.root_color),
            tip_color: share(self.tip_color),
            ..self.clone()
        }
    }
}

/// Which coat a strand belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Coat {
    /// Dense, short hair.
    Undercoat,
    /// Guard hair: sparse, long, thicker.
    Overcoat,
}

/// One hair: a polyline from its root on the skin (z = 0) up to its tip (z = its height).
#[derive(Debug, Clone, PartialEq)]
pub struct Strand {
    /// Root position in `[0, 1)²`.
    pub root: [f64; 2],
    /// Polyline points `(x, y, z)`, root first; `x, y` unwrapped (may leave `[0, 1)`), `z` rises
    /// evenly from 0 to the strand's height.
    pub points: Vec<[f64; 3]>,
    /// Radius at each point, tile units: linear from half the base width to `taper` times that.
    pub radii: Vec<f64>,
    /// Linear color at the root.
    pub root_color: [f32; 3],
    /// Linear color at the tip.
    pub tip_color: [f32; 3],
    /// Undercoat or guard hair.
    pub coat: Coat,
}

impl Strand {
    /// Height of the tip above the skin, in fur depths.
    pub fn height(&self) -> f64 {
        self.points.last().map_or(0.0, |p| p[2])
    }
}

/// Grows the strands of one tile, in Pelt's thread pool.
///
/// Roots are stratified: the tile is cut into the smallest `g × g` grid with `g² >= density`, a
/// seeded shuffle picks `density` distinct cells, and each root is jittered inside its cell. The
/// first `round(guard_fraction · density)` strands (in shuffled order, so spread at random) are
/// guard hairs. The result is bit-identical for any thread count.
///
/// # Errors
/// [`crate::PeltError::InvalidParameter`] when `params` fails [`HairParams::validate`].
pub fn grow_strands(params: &HairParams) -> Result<Vec<Strand>> {
    params.validate()?;
    Ok(pool().install(|| grow_validated(params)))
}

/// Stream ids keep the random sequences of roots, clumps and strands independent.
const STREAM_CELLS: u64 = 1;
const STREAM_CLUMPS: u64 = 2;
const STREAM_STRANDS: u64 = 3;

/// The body of [`grow_strands`], run in whatever pool is current (tests pin the thread count).
fn grow_validated(params: &HairParams) -> Vec<Strand> {
    let n = params.density as usize;
    let (grid, cells) = stratified_cells(n, &mut Rng::stream(params.seed, STREAM_CELLS, 0));
    let mut clump_rng = Rng::stream(params.seed, STREAM_CLUMPS, 0);
    let (clump_grid, clump_cells) = stratified_cells(params.clump_count as usize, &mut clump_rng);
    let clumps: Vec<[f64; 2]> = clump_cells
        .iter()
        .map(|&c| jitter_in_cell(c, clump_grid, &mut clump_rng))
        .collect();
    // `guard_fraction` is in [0, 1] and `n` <= MAX_DENSITY, so the product fits a usize.
    let guards = (params.guard_fraction * n as f64).round() as usize;
    cells
        .par_iter()
        .enumerate()
        .map(|(i, &cell)| {
            let coat = if i < guards {
                Coat::Overcoat
            } else {
                Coat::Undercoat
            };
            grow_one(params, i, cell, grid, coat, &clumps)
        })
        .collect()
}

fn grow_one(
    params: &HairParams,
    index: usize,
    cell: u32,
    grid: usize,
    coat: Coat,
    clumps: &[[f64; 2]],
) -> Strand {
    let mut rng = Rng::stream(params.seed, STREAM_STRANDS, index as u64);
    let root = jitter_in_cell(cell, grid, &mut rng);
    let coat_params = match coat {
        Coat::Undercoat => params.undercoat,
        Coat::Overcoat => params.overcoat,
    };
    let height = lerp(coat_params.length, rng.next_f64()) * (1.0 - params.length_jitter * rng.next_f64());
    let base_radius = 0.5 * lerp(coat_params.width, rng.next_f64());
    let curl_angle = TAU * rng.next_f64();
    let helix_phase = TAU * rng.next_f64();
    let shade = (1.0 - params.color_jitter * rng.next_f64()) as f32;

    let lean = params.slant.tan();
    let (lean_x, lean_y) = (
        lean * params.slant_direction.cos(),
        lean * params.slant_direction.sin(),
    );
    let curl = params.curl * height;
    let (curl_x, curl_y) = (curl * curl_angle.cos(), curl * curl_angle.sin());
    let pull = nearest_clump(root, clumps).map_or([0.0, 0.0], |c| {
        [
            params.clump_strength * (c[0] - root[0]),
            params.clump_strength * (c[1] - root[1]),
        ]
    });

    let segments = params.segments as usize;
    let mut points = Vec::with_capacity(segments + 1);
    let mut radii = Vec::with_capacity(segments + 1);
    for k in 0..=segments {
        let t = k as f64 / segments as f64;
        let z = height * t;
        // The helix starts at the root: subtract its value at t = 0.
        let angle = helix_phase + TAU * params.helix_frequency * t;
        let helix_x = params.helix_radius * (angle.cos() - helix_phase.cos());
        let helix_y = params.helix_radius * (angle.sin() - helix_phase.sin());
        let t2 = t * t;
        points.push([
            root[0] + lean_x * z + curl_x * t2 + helix_x + pull[0] * t,
            root[1] + lean_y * z + curl_y * t2 + helix_y + pull[1] * t,
            z,
        ]);
        radii.push(base_radius * (1.0 - (1.0 - params.taper) * t));
    }
    Strand {
        root,
        points,
        radii,
        root_color: params.root_color.map(|c| c * shade),
        tip_color: params.tip_color.map(|c| c * shade),
        coat,
    }
}

fn lerp(range: [f64; 2], t: f64) -> f64 {
    range[0] + (range[1] - range[0]) * t
}

/// The clump centre nearest to `p` on the torus, as an unwrapped point near `p`.
fn nearest_clump(p: [f64; 2], clumps: &[[f64; 2]]) -> Option<[f64; 2]> {
    clumps
        .iter()
        .map(|c| {
            // Minimum image: the copy of the centre within half a tile of `p` on each axis.
            let dx = c[0] - p[0] - (c[0] - p[0]).round();
            let dy = c[1] - p[1] - (c[1] - p[1]).round();
            (dx * dx + dy * dy, [p[0] + dx, p[1] + dy])
        })
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, c)| c)
}

/// Side `g` of the smallest square grid with `g² >= n`, and `n` distinct cells of it in seeded
/// random order (a partial Fisher–Yates shuffle), so no cell holds two points.
fn stratified_cells(n: usize, rng: &mut Rng) -> (usize, Vec<u32>) {
    let mut g = (n as f64).sqrt() as usize;
    while g * g < n {
        g += 1;
    }
    // g² < 2²¹ because n <= MAX_DENSITY (and MAX_CLUMPS), so cells fit a u32.
    let mut cells: Vec<u32> = (0..(g * g) as u32).collect();
    for i in 0..n {
        let j = i + rng.below((cells.len() - i) as u64) as usize;
        cells.swap(i, j);
    }
    cells.truncate(n);
    (g, cells)
}

/// A uniform point inside cell `cell` of a `grid × grid` tiling of `[0, 1)²`.
fn jitter_in_cell(cell: u32, grid: usize, rng: &mut Rng) -> [f64; 2] {
    let (cx, cy) = (cell as usize % grid, cell as usize / grid);
    // (g - 1 + u) / g can round up to 1.0; the largest f64 below 1 keeps roots in [0, 1).
    let below_one = 1.0 - f64::EPSILON / 2.0;
    let x = ((cx as f64 + rng.next_f64()) / grid as f64).min(below_one);
    let y = ((cy as f64 + rng.next_f64()) / grid as f64).min(below_one);
    [x, y]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::PeltError;

    fn grow_with_threads(params: &HairParams, threads: usize) -> Vec<Strand> {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| grow_validated(params))
    }

    fn bits(strands: &[Strand]) -> Vec<u64> {
        let mut out = Vec::new();
        for s in strands {
            out.extend(s.root.iter().map(|v| v.to_bits()));
            out.extend(s.points.iter().flatten().map(|v| v.to_bits()));
            out.extend(s.radii.iter().map(|v| v.to_bits()));
            out.extend(
                s.root_color
                    .iter()
                    .chain(&s.tip_color)
                    .map(|v| u64::from(v.to_bits())),
            );
            out.push(s.coat as u64);
        }
        out
    }

    #[test]
    fn default_validates_and_grows_density_strands() {
        let params = HairParams::default();
        params.validate().unwrap();
        let strands = grow_strands(&params).unwrap();
        assert_eq!(strands.len(), params.density as usize);
        let guards = strands.iter().filter(|s| s.coat == Coat::Overcoat).count();
        assert_eq!(guards, 819, "round(0.05 * 16384)");
    }

    #[test]
    fn every_out_of_range_field_is_named() {
        type Breaker = fn(&mut HairParams);
        let cases: &[(&str, Breaker)] = &[
            ("density", |p| p.density = MAX_DENSITY + 1),
            ("guard_fraction", |p| p.guard_fraction = 1.5),
            ("guard_fraction", |p| p.guard_fraction = f64::NAN),
            ("undercoat.length", |p| p.undercoat.length = [-0.1, 0.5]),
            ("undercoat.length", |p| p.undercoat.length = [0.7, 0.5]),
            ("undercoat.width", |p| p.undercoat.width = [0.0, 0.2]),
            ("overcoat.length", |p| p.overcoat.length = [0.5, 1.1]),
            ("overcoat.width", |p| p.overcoat.width = [0.01, 0.005]),
            ("segments", |p| p.segments = 0),
            ("segments", |p| p.segments = MAX_SEGMENTS + 1),
            ("taper", |p| p.taper = -0.01),
            ("curl", |p| p.curl = 1.01),
            ("helix_radius", |p| p.helix_radius = 0.2),
            ("helix_frequency", |p| p.helix_frequency = -1.0),
            ("slant", |p| p.slant = 1.5),
            ("slant_direction", |p| p.slant_direction = 7.0),
            ("length_jitter", |p| p.length_jitter = 2.0),
            ("clump_strength", |p| p.clump_strength = f64::INFINITY),
            ("clump_count", |p| p.clump_count = MAX_CLUMPS + 1),
            ("root_color", |p| p.root_color = [0.5, 1.5, 0.5]),
            ("tip_color", |p| p.tip_color = [f32::NAN, 0.0, 0.0]),
            ("color_jitter", |p| p.color_jitter = -1.0),
        ];
        for (field, breaker) in cases {
            let mut params = HairParams::default();
            breaker(&mut params);
            match params.validate() {
                Err(PeltError::InvalidParameter { name, reason }) => {
                    assert_eq!(&name, field, "{reason}");
                    assert!(reason.contains("must be"), "{reason}");
                }
                other => panic!("{field}: expected InvalidParameter, got {other:?}"),
            }
            assert!(grow_strands(&params).is_err(), "{field}");
        }
    }

    #[test]
    fn under_paint_keeps_the_coats_shading_and_leaves_its_color_to_the_paint() {
        let coat = HairParams {
            root_color: [0.12, 0.5, 0.0],
            tip_color: [0.48, 0.25, 0.0],
            ..HairParams::default()
        };
        assert_eq!(coat.under_paint(false), coat);
        let painted = coat.under_paint(true);
        // Per channel: the brighter end at 1, the other at its share of it; black stays neutral.
        assert_eq!(painted.tip_color, [1.0, 0.5, 1.0]);
        assert_eq!(painted.root_color, [0.25, 1.0, 1.0]);
        assert!(painted.validate().is_ok());
        assert_eq!(
            HairParams {
                root_color: coat.root_color,
                tip_color: coat.tip_color,
                ..painted
            },
            coat
        );
    }

    #[test]
    fn zero_density_gives_no_strands() {
        let params = HairParams {
            density: 0,
            ..HairParams::default()
        };
        assert!(grow_strands(&params).unwrap().is_empty());
    }

    #[test]
    fn same_seed_is_bitwise_identical_and_other_seeds_differ() {
        let params = HairParams {
            clump_count: 20,
            clump_strength: 0.5,
            helix_radius: 0.01,
            helix_frequency: 3.0,
            ..HairParams::default()
        };
        let a = bits(&grow_strands(&params).unwrap());
        let b = bits(&grow_strands(&params).unwrap());
        assert_eq!(a, b);
        let other = HairParams {
            seed: params.seed + 1,
            ..params.clone()
        };
        let c = bits(&grow_strands(&other).unwrap());
        assert_eq!(a.len(), c.len());
        let same = a.iter().zip(&c).filter(|(x, y)| x == y).count();
        // Only the z = 0 of each root point and the coat tags may coincide.
        assert!(same < a.len() / 10, "{same} of {} words equal", a.len());
    }

    #[test]
    fn one_and_four_threads_agree_bitwise() {
        let params = HairParams {
            density: 10_000,
            clump_count: 30,
            clump_strength: 0.3,
            ..HairParams::default()
        };
        assert_eq!(
            bits(&grow_with_threads(&params, 1)),
            bits(&grow_with_threads(&params, 4))
        );
    }

    fn cell_counts(strands: &[Strand], grid: usize) -> Vec<usize> {
        let mut counts = vec![0; grid * grid];
        for s in strands {
            let [x, y] = s.root;
            assert!((0.0..1.0).contains(&x) && (0.0..1.0).contains(&y), "{x} {y}");
            counts[(y * grid as f64) as usize * grid + (x * grid as f64) as usize] += 1;
        }
        counts
    }

    #[test]
    fn roots_are_stratified() {
        // Default density 16384 = 128²: exactly one root per cell.
        let strands = grow_strands(&HairParams::default()).unwrap();
        assert!(cell_counts(&strands, 128).iter().all(|&c| c == 1));
        // 1000 hairs: 32² = 1024 cells, 1000 of them hold one root, none holds two.
        let params = HairParams {
            density: 1000,
            ..HairParams::default()
        };
        let counts = cell_counts(&grow_strands(&params).unwrap(), 32);
        assert_eq!(counts.iter().filter(|&&c| c == 1).count(), 1000);
        assert!(counts.iter().all(|&c| c <= 1));
    }

    #[test]
    fn radius_tapers_linearly_and_height_rises_evenly() {
        let params = HairParams {
            taper: 0.3,
            ..HairParams::default()
        };
        for s in grow_strands(&params).unwrap() {
            let n = s.radii.len() - 1;
            assert_eq!(n, params.segments as usize);
            let (base, tip) = (s.radii[0], s.radii[n]);
            let width = match s.coat {
                Coat::Undercoat => params.undercoat.width,
                Coat::Overcoat => params.overcoat.width,
            };
            assert!(2.0 * base >= width[0] - 1e-15 && 2.0 * base <= width[1] + 1e-15);
            assert!((tip - 0.3 * base).abs() <= 1e-15);
            let height = s.points[n][2];
            for k in 0..=n {
                let t = k as f64 / n as f64;
                assert!((s.radii[k] - (base + (tip - base) * t)).abs() <= 1e-15);
                assert!((s.points[k][2] - height * t).abs() <= 1e-15);
            }
            assert_eq!(s.points[0], [s.root[0], s.root[1], 0.0]);
        }
    }

    #[test]
    fn straight_hair_without_jitter_stands_up() {
        // No slant, curl, helix or clumping: every point sits above its root.
        let params = HairParams {
            curl: 0.0,
            slant: 0.0,
            length_jitter: 0.0,
            ..HairParams::default()
        };
        for s in grow_strands(&params).unwrap() {
            for p in &s.points {
                assert_eq!([p[0], p[1]], s.root);
            }
        }
    }

    #[test]
    fn clumping_pulls_tips_together() {
        let spread = |strength: f64| {
            let params = HairParams {
                clump_count: 16,
                clump_strength: strength,
                curl: 0.0,
                slant: 0.0,
                ..HairParams::default()
            };
            let strands = grow_strands(&params).unwrap();
            // Tip distance to the nearest other tip, averaged over the first 200 strands.
            let tips: Vec<[f64; 2]> = strands
                .iter()
                .map(|s| {
                    let p = s.points[s.points.len() - 1];
                    [p[0].rem_euclid(1.0), p[1].rem_euclid(1.0)]
                })
                .collect();
            tips.iter()
                .take(200)
                .enumerate()
                .map(|(i, a)| {
                    tips.iter()
                        .enumerate()
                        .filter(|&(j, _)| j != i)
                        .map(|(_, b)| {
                            let dx = a[0] - b[0] - (a[0] - b[0]).round();
                            let dy = a[1] - b[1] - (a[1] - b[1]).round();
                            (dx * dx + dy * dy).sqrt()
                        })
                        .fold(f64::INFINITY, f64::min)
                })
                .sum::<f64>()
                / 200.0
        };
        assert!(spread(0.9) < 0.5 * spread(0.0));
    }

    #[test]
    fn params_round_trip_through_json() {
        let params = HairParams {
            seed: 42,
            ..HairParams::default()
        };
        let text = serde_json::to_string(&params).unwrap();
        assert_eq!(serde_json::from_str::<HairParams>(&text).unwrap(), params);
        let partial: HairParams = serde_json::from_str(r#"{"density": 9}"#).unwrap();
        assert_eq!(partial.density, 9);
        assert_eq!(partial.taper, HairParams::default().taper);
    }
}
