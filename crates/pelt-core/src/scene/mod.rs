//! The fur's geometry prepared for drawing, without a GPU (Lengyel et al. 2001, §2.3–§2.4): the
//! skin split at patch seams with its per-vertex frames ([`surface_mesh`], [`deform`] in a pose or
//! with a new comb), the fin quads ([`fin_mesh`]), simplified levels of the mesh
//! ([`geometry_lod`], [`scene_levels`]) and whether they still hold after a repaint
//! ([`level_hosts`]), and the fins a view draws ([`fin_cull`], [`fin_pose`]). The renderer
//! (`pelt-render`) uploads and draws what this module computes; the vertex types are `Pod`, laid
//! out as its shaders read them.

pub mod curvature;
pub mod deform;
pub mod fin_cull;
pub mod fin_mesh;
pub mod fin_pose;
pub mod geometry_lod;
pub mod level_hosts;
pub mod scene_levels;
pub mod surface_mesh;
