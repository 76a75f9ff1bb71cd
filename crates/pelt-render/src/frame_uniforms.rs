//! The uniform block every fur pass reads (`Frame` in `common.wgsl`), packed from the camera,
//! lighting and settings of one frame and the scene it draws.

use bytemuck::{Pod, Zeroable};

use super::camera::CameraFrame;
use super::lighting::LightingFrame;
use super::lod::{FrameInfo, Levels};
use super::settings::RenderSettings;
use super::shadow_map::ShadowFrame;

/// Mirrors `Frame` in `common.wgsl`: a matrix and `vec4`s only, so the Rust and WGSL layouts
/// agree without padding rules.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub(super) struct FrameUniforms {
    view_proj: [f32; 16],
    eye: [f32; 4],
    light_direction: [f32; 4],
    light_color: [f32; 4],
    ambient: [f32; 4],
    kajiya_kay: [f32; 4],
    fur: [f32; 4],
    fin: [f32; 4],
    counts: [u32; 4],
    lod: [u32; 4],
    prt: [u32; 4],
    strand: [f32; 4],
    strand_counts: [u32; 4],
    planes: [f32; 4],
    goldman: [f32; 4],
    ambient_gradient: [[f32; 4]; 3],
    light_view_proj: [f32; 16],
    shadow: [f32; 4],
    fin_tangents: [[f32; 4]; 2],
    stand: [[f32; 4]; STAND_ROWS],
}

/// Rows of `Frame::stand`: four heights each, enough for level 1 and level 2 of the most layers
/// a volume may have (`1 + 255 / 2` and `1 + 255 / 4`, 194 in all).
pub(super) const STAND_ROWS: usize = 64;

/// The scene's side of the frame.
pub(super) struct SceneFrame<'a> {
    /// What the frame draws.
    pub info: &'a FrameInfo,
    /// The shell array's levels.
    pub levels: &'a Levels,
    /// Per array layer of every level, the level-0 height it stands at.
    pub stand_heights: &'a [f32],
    /// Layers of the shell texture.
    pub layers: u32,
    /// Fur depth in object units ([`super::FurScene::fur_depth`]).
    pub fur_depth: f32,
    /// Height between layers, share of the fur depth.
    pub layer_spacing: f32,
    /// PRT: coefficients, transfer textures, array layers per texture (zero without PRT).
    pub prt: [u32; 3],
    /// The drawn geometric level's fin spacing over the full mesh's ([`pelt_core::scene::scene_levels::MeshLevel`]).
    pub fin_spacing: f32,
    /// The guard strands' row of the uniforms: `strand` and `strand_counts` of `Frame`.
    pub strand: ([f32; 4], [u32; 4]),
    /// The virtual planes' count and lean (zero without slices).
    pub planes: (u32, [f32; 2]),
    /// Where the body's shadow map is looked up ([`ShadowFrame::NONE`] when it is not drawn).
    pub shadow: ShadowFrame,
    /// The hair directions' second moment (`tangent_spread.rs`), which lights the fins.
    pub fin_tangents: [[f32; 4]; 2],
}

impl FrameUniforms {
    pub fn new(
        camera: &CameraFrame,
        light: &LightingFrame,
        settings: &RenderSettings,
        scene: &SceneFrame<'_>,
    ) -> Self {
        let (info, levels) = (scene.info, scene.levels);
        let k = info.level as usize;
        let coarse = levels.bases.get(k + 1).copied().unwrap_or(levels.bases[k]);
        let v3 = |v: [f32; 3]| [v[0], v[1], v[2], 0.0];
        let (stand, coarse_stand) = stand_rows(scene, settings.lod);
        FrameUniforms {
            view_proj: camera.view_proj.to_cols_array(),
            eye: camera.eye.to_array(),
            light_direction: {
                let [x, y, z] = light.direction;
                [x, y, z, light.hot_spot_share()]
            },
            light_color: v3(light.color),
            ambient: v3(light.ambient),
            kajiya_kay: light.kajiya_kay,
            fur: [
                scene.fur_depth,
                scene.layer_spacing,
                light.self_shadow,
                // Less a half float's rounding: stored in half floats (a CPU adapter's color
                // textures), an opacity of exactly the threshold reads up to 2⁻¹¹ below it.
                settings.alpha_test * (1.0 - 1.0 / 2048.0),
            ],
            fin: [settings.fin_opacity, info.blend, scene.fin_spacing, 0.0],
            counts: [info.shells, scene.layers, u32::from(settings.lod), coarse_stand],
            lod: [
                levels.bases[k],
                coarse,
                1 << info.level,
                levels.counts.get(k + 1).copied().unwrap_or(0),
            ],
            prt: [scene.prt[0], scene.prt[1], scene.prt[2], scene.layers],
            strand: scene.strand.0,
            strand_counts: scene.strand.1,
            planes: [
                scene.planes.0 as f32,
                settings.plane_loop_limit as f32,
                scene.planes.1[0],
                scene.planes.1[1],
            ],
            goldman: [light.goldman[0], light.goldman[1], 0.0, 0.0],
            ambient_gradient: light.ambient_gradient.map(v3),
            light_view_proj: scene.shadow.light_view_proj.to_cols_array(),
            shadow: scene.shadow.params,
            fin_tangents: scene.fin_tangents,
            stand,
        }
    }
}

/// `Frame::stand` and where the coarser level's heights start in it: under LOD, the heights of
/// the drawn level's layers (none at level 0, whose layers stand at their own height), then the
/// next coarser level's.
fn stand_rows(scene: &SceneFrame<'_>, lod: bool) -> ([[f32; 4]; STAND_ROWS], u32) {
    let (levels, k) = (scene.levels, scene.info.level as usize);
    let level = |k: usize| {
        let base = levels.bases[k] as usize;
        &scene.stand_heights[base..base + levels.counts[k] as usize]
    };
    let drawn: &[f32] = if lod && k > 0 { level(k) } else { &[] };
    let coarser: &[f32] = if lod && k + 1 < levels.counts.len() {
        level(k + 1)
    } else {
        &[]
    };
    let mut rows = [[0.0; 4]; STAND_ROWS];
    for (i, &h) in drawn.iter().chain(coarser).take(4 * STAND_ROWS).enumerate() {
        rows[i / 4][i % 4] = h;
    }
    (rows, drawn.len() as u32)
}
