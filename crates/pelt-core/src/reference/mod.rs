//! The reference (ground-truth) fur renderer: the very strands the volume was sampled from, placed
//! over the mesh as the shells imply and ray traced, so that every preview can be measured
//! against what its approximations stand for.
//!
//! - Geometry ([`geometry`]): each strand of the tile is instantiated wherever a triangle's patch
//!   UVs cover its root, every point carried to the surface by the map of the triangle whose UVs
//!   hold it (found by walking across edges inside the patch), lifted along the same growth
//!   direction and by the same per-vertex length as the shells (`mesh::shell_offset`), as a
//!   tapered cylinder of the strand's width.
//! - Tracing ([`scene`]): one compressed wide BVH (the `obvhs` crate: a PLOC build, 8-wide SIMD
//!   traversal; no BVH crate intersects tapered hair, so the primitive tests are ours,
//!   [`intersect`]) over chunks of strand segments and the skin's triangles.
//! - Shading ([`shade`]): the preview's Kajiya–Kay terms (Lengyel et al. 2001, §2.4) as a
//!   single-scattering phase (the hybrid paper's model) with exact shadow rays through the strands
//!   and the skin toward each light; the skin Lambertian. Lights ([`light`]) in Blender's units:
//!   a sun of strength `E` gives a white Lambertian surface facing it the radiance `E / π`.
//! - Convergence ([`render`]): progressive passes until the relative standard error of the
//!   image's mean radiance is within a target; the achieved error comes with every image.
//!
//! - Volume mode ([`volume`], [`density`]): the hybrid paper's own method, the bake's density
//!   volume ray marched through the prisms the triangles extrude, with single scattering and
//!   attenuation toward light and eye, rendered by the same loop
//!   ([`render::render_volume_reference`]).
//!
//! The renderer shares nothing with the shells, fins, PRT or the wgpu passes beyond the mesh, the
//! patches, the strand list and (volume mode) the baked volume.

mod bvh;
pub mod camera;
mod density;
pub mod geometry;
mod intersect;
pub mod light;
#[cfg(feature = "metrics")]
pub mod metrics;
pub mod render;
mod sampler;
pub mod scene;
pub mod scenes;
mod settings;
pub mod shade;
pub mod volume;

#[cfg(test)]
mod tests;

pub use geometry::{FurGeometry, WorldStrand};
pub use light::ReferenceLight;
pub use render::{ReferenceImage, ReferenceSettings, render_reference, render_volume_reference};
pub use scene::ReferenceScene;
pub use shade::HairShading;
pub use volume::VolumeScene;
