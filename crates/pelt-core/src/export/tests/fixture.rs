//! A small furred object for the glTF and texture-set tests: a UV sphere with painted colors,
//! comb and lengths (a bald cap at the south pole), lapped patches, a small hair volume and
//! order-2 transfer textures packed from pseudo-random coefficients.

use crate::export::{ExportInput, TransferTextures};
use crate::hair::HairParams;
use crate::lapped::{PatchParams, build_patches};
use crate::mesh::shapes::{uv_sphere, uv_sphere_polygons};
use crate::prt::Transfer;
use crate::prt::pack::{PackedF16, PackedU8, pack_f16, pack_u8};
use crate::rng::Rng;
use crate::volume::{HairVolume, VolumeParams, bake_volume};
use crate::{FurMesh, MeshInput};

pub(super) struct Fixture {
    pub mesh: FurMesh,
    pub uvs: Vec<[[f32; 2]; 3]>,
    pub volume: HairVolume,
    pub f16: PackedF16,
    pub u8: PackedU8,
}

pub(super) const ORDER: usize = 2;
pub(super) const FUR_DEPTH: f64 = 0.2;

impl Fixture {
    pub fn new() -> Self {
        let (segments, rings) = (12, 8);
        let (positions, triangles) = uv_sphere(segments, rings);
        let polygons = uv_sphere_polygons(segments, rings);
        let n = positions.len();
        // Colors outside [0, 1] in places: glTF's COLOR_0 is clamped.
        let color: Vec<[f32; 4]> = positions
            .iter()
            .map(|p| [0.5 + 0.7 * p[0], 0.5 + 0.5 * p[1], 0.3, 1.0])
            .collect();
        let comb: Vec<[f32; 3]> = positions.iter().map(|p| [0.3, 0.1 * p[2], 0.0]).collect();
        // Bald below z = −0.8 (the southern cap), longer toward the north.
        let length: Vec<f32> = positions
            .iter()
            .map(|p| if p[2] < -0.8 { 0.0 } else { 1.0 + 0.5 * p[2] })
            .collect();
        assert_eq!(length.len(), n);
        let mesh = FurMesh::new(
            MeshInput::new(&positions, &triangles)
                .with_color(&color)
                .with_comb(&comb)
                .with_length(&length)
                .with_polygons(&polygons),
        )
        .unwrap();
        let patches = build_patches(
            &mesh,
            &PatchParams {
                tile_size: 0.6,
                ..PatchParams::default()
            },
        )
        .unwrap();
        let hair = HairParams {
            density: 600,
            ..HairParams::default()
        };
        let params = VolumeParams {
            resolution: 16,
            layers: 6,
            fin_size: [32, 8],
            trim: false,
            ..VolumeParams::default()
        };
        let volume = bake_volume(&hair, &params, None).unwrap();
        let mut rng = Rng::new(7);
        let count = volume.layers * volume.resolution * volume.resolution * ORDER * ORDER;
        let transfer = Transfer {
            order: ORDER,
            layers: volume.layers,
            resolution: volume.resolution,
            coefficients: (0..count).map(|_| rng.next_f64() as f32 * 2.0 - 0.5).collect(),
        };
        Fixture {
            mesh,
            uvs: patches.uv,
            f16: pack_f16(&transfer).unwrap(),
            u8: pack_u8(&transfer).unwrap(),
            volume,
        }
    }

    pub fn input<'a>(&'a self, name: &'a str) -> ExportInput<'a> {
        ExportInput {
            name,
            mesh: &self.mesh,
            corner_uvs: &self.uvs,
            volume: &self.volume,
            transfer: Some(TransferTextures {
                order: ORDER,
                f16: &self.f16,
                u8: &self.u8,
            }),
            fur_depth: FUR_DEPTH,
            shells: None,
            transform: Default::default(),
            skin: None,
            materials: None,
            animations: &[],
            guard_hairs: None,
        }
    }
}
