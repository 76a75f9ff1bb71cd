//! A scene's geometric levels of detail made anew under repainted colors and lengths. The levels
//! were simplified under the attributes the scene was uploaded with, the simplifier weighing them
//! in its metric (`pelt_core::scene::geometry_lod`); a repaint that a level cannot hold stops it
//! being drawn ([`FurScene::update_attributes`]), so far away the full mesh is drawn, several
//! times the triangles. Simplifying again under the new attributes gives levels that hold them.
//! It costs about as much as the upload's simplification (a tenth of a second on 60k triangles
//! on one core), so the live preview does it once a stroke has settled, not per dab.

use super::scene::{FurScene, GpuMesh};
use super::{Renderer, scoped};
use pelt_core::error::{PeltError, Result};
use pelt_core::scene::fin_cull::FinPlanes;
use pelt_core::scene::scene_levels::{self, SceneLevels};
use pelt_core::scene::surface_mesh::expand;
use pelt_core::threads::pool;

impl FurScene {
    /// Whether a repaint left some coarser geometric levels undrawn, which
    /// [`FurScene::remake_levels`] would make anew.
    pub fn levels_dropped(&self) -> bool {
        self.drawable < self.mesh_levels.len()
    }

    /// Simplifies the mesh again under the current colors and lengths when a repaint left
    /// levels undrawn ([`FurScene::levels_dropped`]), and uploads the new levels: their
    /// triangles, written into the surface's index buffer, and their fins. Returns whether it
    /// made them; the picture is the same up to the levels' error bound, and frames far away
    /// draw a coarser level again.
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] naming `renderer` (not the one that uploaded the scene);
    /// [`PeltError::Render`] when the device fails. The scene is unchanged then.
    pub fn remake_levels(&mut self, renderer: &Renderer) -> Result<bool> {
        if renderer.id != self.renderer_id() {
            return Err(PeltError::parameter(
                "renderer",
                "is not the Renderer that uploaded this scene",
            ));
        }
        if !self.levels_dropped() {
            return Ok(false);
        }
        let (colors, lengths) = (&self.attributes.0, &self.attributes.1);
        let surface = &self.rest_surface;
        let SceneLevels {
            levels,
            surface_indices,
            fins,
            hosts,
        } = pool().install(|| {
            let surface_colors = expand(colors, &surface.source);
            let surface_lengths = expand(lengths, &surface.source);
            SceneLevels::new(
                self.deformer.rest(),
                surface,
                (colors, lengths),
                (&surface_colors, &surface_lengths),
            )
        });
        let index_bytes = 4 * surface_indices.len() as u64;
        if index_bytes > self.surface.index.size() {
            // Each level has at most half the triangles of the one above, so this cannot happen.
            return Err(PeltError::Render(format!(
                "the remade levels' {index_bytes} index bytes exceed the buffer's {}",
                self.surface.index.size()
            )));
        }
        let fins_gpu = scoped(&renderer.device, "uploading the remade levels", || {
            GpuMesh::fins(&renderer.device, &fins, (colors, lengths))
        })?;
        self.queue
            .write_buffer(&self.surface.index, 0, bytemuck::cast_slice(&surface_indices));
        self.shadow.set_drawn(None);
        self.queue.submit(std::iter::empty());
        self.fins = fins_gpu;
        self.uploads.geometry_bytes += index_bytes
            + (size_of_val(fins.vertices.as_slice()) + size_of_val(fins.indices.as_slice())) as u64;
        self.uploads.attribute_bytes += fins.source.len() as u64 * (16 + 4);
        let ends = fins.ends();
        self.fin_planes
            .get_mut()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .replace(
                FinPlanes::new(fins.centers, fins.normals),
                ends,
                levels.iter().map(|l| l.fins.clone()),
            );
        self.drawable = scene_levels::drawable(&hosts, colors, lengths);
        self.fin_source = fins.source;
        self.mesh_levels = levels;
        self.level_hosts = hosts;
        Ok(true)
    }
}
