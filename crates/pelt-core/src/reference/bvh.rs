//! The reference's acceleration structure: `obvhs`'s compressed 8-wide BVH (Ylitie et al. 2017)
//! built by PLOC with reinsertion, over boxes of any primitive. The build runs in Pelt's pool;
//! the renderer's results never depend on the tree's shape (nearest hits and any-hit queries
//! have one answer whatever the traversal order).

use std::time::Duration;

use glam::Vec3A;
use obvhs::BvhBuildParams;
use obvhs::aabb::Aabb;
use obvhs::cwbvh::CwBvh;
use obvhs::cwbvh::builder::build_cwbvh;
use obvhs::ray::{Ray, RayHit};

use crate::threads::pool;

/// The six axis directions, for the inside test of a closed skin (a point is enclosed when the
/// nearest skin along each of them is a back face).
pub(crate) const AXIS_DIRECTIONS: [Vec3A; 6] = [
    Vec3A::X,
    Vec3A::NEG_X,
    Vec3A::Y,
    Vec3A::NEG_Y,
    Vec3A::Z,
    Vec3A::NEG_Z,
];

pub(crate) struct Bvh {
    tree: CwBvh,
}

impl Bvh {
    /// A tree over `boxes`; primitive `i` is `boxes[i]`.
    pub(crate) fn new(boxes: &[Aabb]) -> Self {
        let tree =
            pool().install(|| build_cwbvh(boxes, BvhBuildParams::fast_build(), &mut Duration::default()));
        Bvh { tree }
    }

    /// A ray for the traversal. Signed zeros become +0: the traversal picks its octant from the
    /// sign bits, and a −0 component sent every ray along that axis down the wrong children.
    pub(crate) fn ray(origin: Vec3A, direction: Vec3A, t_min: f32, t_max: f32) -> Ray {
        Ray::new(origin, direction + Vec3A::ZERO, t_min, t_max)
    }

    pub(crate) fn bounds(&self) -> Aabb {
        self.tree.total_aabb
    }

    /// Calls `test(ray, primitive)` for the primitives the ray may hit, nearest boxes first;
    /// `test` returns the hit's `t` (or infinity), which then bounds the ray.
    pub(crate) fn nearest(&self, ray: Ray, mut test: impl FnMut(&Ray, usize) -> f32) {
        let mut hit = RayHit::none();
        let indices = &self.tree.primitive_indices;
        self.tree
            .ray_traverse(ray, &mut hit, |ray, id| test(ray, indices[id] as usize));
    }

    /// Whether `test(ray, primitive)` holds for any primitive the ray may hit; stops at the
    /// first.
    pub(crate) fn any(&self, ray: Ray, mut test: impl FnMut(&Ray, usize) -> bool) -> bool {
        let indices = &self.tree.primitive_indices;
        !self.tree.ray_traverse_miss(ray, |ray, id| {
            if test(ray, indices[id] as usize) {
                0.0
            } else {
                f32::INFINITY
            }
        })
    }
}
