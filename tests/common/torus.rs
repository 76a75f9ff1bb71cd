//! The render tests' furred torus on the CPU adapter: a torus mesh with parametric tile UVs
//! (split where the ring and the tube close, a seam as between patches) and the small hair
//! volume, for tests that render it with passes or settings changed.

use glam::DMat4;
use pelt::mesh::shapes::{torus, torus_uvs};
use pelt::render::{AdapterChoice, Camera, FurScene, Lighting, RenderSettings, Renderer, RgbaImage};
use pelt::volume::HairVolume;
use pelt::{FurMesh, MeshInput};

use super::volume::small_volume;
use super::{column_major, perspective, view_matrix};

pub struct FurredTorus {
    pub renderer: Renderer,
    pub mesh: FurMesh,
    pub uvs: Vec<[[f32; 2]; 3]>,
    pub volume: HairVolume,
    /// Fur depth of the scenes, object units.
    pub fur_depth: f32,
}

impl FurredTorus {
    /// `around` × `across` quads, the tile repeating `repeats` times around the ring and the
    /// tube, an 8-layer volume, fur `fur_depth` object units deep; the test fails (never skips)
    /// without a CPU adapter.
    pub fn new(around: usize, across: usize, repeats: [f32; 2], fur_depth: f32) -> Self {
        let renderer =
            Renderer::new(AdapterChoice::Cpu).expect("a CPU adapter (lavapipe) must exist under make test");
        let (positions, triangles) = torus(around, across);
        FurredTorus {
            renderer,
            mesh: FurMesh::new(MeshInput::new(&positions, &triangles)).unwrap(),
            uvs: torus_uvs(around, across, repeats),
            volume: small_volume(8),
            fur_depth,
        }
    }

    /// The torus uploaded.
    pub fn scene(&self) -> FurScene {
        self.scene_of(&self.mesh)
    }

    /// `mesh` (the torus's vertices and triangles, moved or combed) uploaded with the torus's
    /// UVs, volume and fur depth.
    pub fn scene_of(&self, mesh: &FurMesh) -> FurScene {
        FurScene::new(&self.renderer, mesh, &self.uvs, &self.volume, self.fur_depth).unwrap()
    }

    /// `scene` under the default lighting.
    pub fn render(&self, scene: &FurScene, camera: &Camera, settings: &RenderSettings) -> RgbaImage {
        self.renderer
            .render(scene, camera, &Lighting::default(), settings)
            .unwrap()
    }
}

/// Pixels with any coverage.
pub fn covered(image: &RgbaImage) -> usize {
    image.pixels.chunks_exact(4).filter(|p| p[3] > 0).count()
}

/// Share of pixels whose channels differ by more than `tolerance` levels.
pub fn differing(a: &RgbaImage, b: &RgbaImage, tolerance: u8) -> f64 {
    let count = a
        .pixels
        .chunks_exact(4)
        .zip(b.pixels.chunks_exact(4))
        .filter(|(p, q)| p.iter().zip(*q).any(|(x, y)| x.abs_diff(*y) > tolerance))
        .count();
    count as f64 / (a.pixels.len() / 4) as f64
}

/// A perspective camera (60°) of `size²` pixels whose view matrix is `view` (object to eye).
pub fn perspective_camera(view: DMat4, size: u32) -> Camera {
    Camera {
        view: view.as_mat4().to_cols_array(),
        projection: column_major(perspective(60.0, 0.5, 10.0)),
        width: size,
        height: size,
    }
}

/// The view from above and to the side of the torus, looking at its centre.
pub fn oblique_view() -> DMat4 {
    view_matrix([0.0, -2.6, 2.2], [0.0; 3], [0.0, 0.0, 1.0])
}
