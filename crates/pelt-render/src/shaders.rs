//! The fur passes' shaders, composed from WGSL modules by naga_oil. Each shared file names itself
//! after its stem (`#define_import_path pelt::surface` in `surface.wgsl`) and imports what it
//! uses. A pass's shader ([`PassShader`], one per pass file) is one source for both lighting
//! models: the shader def `PRT` picks the model's modules (`light_model.wgsl` states what each
//! model provides). Each is composed once per model and process, on first use, and reaches wgpu
//! as naga IR (no second WGSL parse; wgpu still validates it).

use std::collections::HashMap;
use std::sync::{LazyLock, Mutex, OnceLock, PoisonError};

use naga_oil::compose::{
    ComposableModuleDescriptor, Composer, ComposerError, NagaModuleDescriptor, ShaderDefValue,
};
use pelt_core::error::{PeltError, Result};
use wgpu::naga::Module;

use super::pass::Model;

/// The shared modules, each after the modules it imports (naga_oil's order of adding them).
const MODULES: [(&str, &str); 14] = [
    ("body_shadow.wgsl", include_str!("body_shadow.wgsl")),
    ("common.wgsl", include_str!("common.wgsl")),
    ("light_model.wgsl", include_str!("light_model.wgsl")),
    ("lighting.wgsl", include_str!("lighting.wgsl")),
    ("hot_spot.wgsl", include_str!("hot_spot.wgsl")),
    ("prt.wgsl", include_str!("prt.wgsl")),
    ("surface.wgsl", include_str!("surface.wgsl")),
    ("surface_kk.wgsl", include_str!("surface_kk.wgsl")),
    ("surface_prt.wgsl", include_str!("surface_prt.wgsl")),
    ("march.wgsl", include_str!("march.wgsl")),
    ("fin_kk.wgsl", include_str!("fin_kk.wgsl")),
    ("fin_prt.wgsl", include_str!("fin_prt.wgsl")),
    ("strand_kk.wgsl", include_str!("strand_kk.wgsl")),
    ("strand_prt.wgsl", include_str!("strand_prt.wgsl")),
];

/// The composer holding [`MODULES`], or why one of them was refused.
static COMPOSER: LazyLock<Mutex<std::result::Result<Composer, String>>> =
    LazyLock::new(|| Mutex::new(composer()));

fn composer() -> std::result::Result<Composer, String> {
    let mut composer = Composer::default();
    for (file, source) in MODULES {
        let added = composer
            .add_composable_module(ComposableModuleDescriptor {
                source,
                file_path: file,
                ..Default::default()
            })
            .map(|_| ());
        added.map_err(|e| failure(&composer, file, &e))?;
    }
    Ok(composer)
}

fn failure(composer: &Composer, file: &str, e: &ComposerError) -> String {
    format!("composing {file} failed: {}", e.emit_to_string(composer))
}

/// A pass's shader and its composed module per lighting model.
pub(super) struct PassShader {
    file: &'static str,
    source: &'static str,
    /// Indexed by `model == Model::Prt`.
    composed: [OnceLock<std::result::Result<Module, String>>; 2],
}

impl PassShader {
    pub const fn new(file: &'static str, source: &'static str) -> Self {
        PassShader {
            file,
            source,
            composed: [OnceLock::new(), OnceLock::new()],
        }
    }

    /// The shader under `model`, composed on first use.
    ///
    /// # Errors
    /// [`PeltError::Render`] when it does not compose or validate (a bug in the WGSL).
    pub fn module(&'static self, model: Model) -> Result<&'static Module> {
        self.composed[usize::from(model == Model::Prt)]
            .get_or_init(|| self.compose(model))
            .as_ref()
            .map_err(|e| PeltError::Render(e.clone()))
    }

    fn compose(&self, model: Model) -> std::result::Result<Module, String> {
        let mut guard = COMPOSER.lock().unwrap_or_else(PoisonError::into_inner);
        let composer = guard.as_mut().map_err(|e| e.clone())?;
        let mut shader_defs = HashMap::new();
        if model == Model::Prt {
            shader_defs.insert("PRT".to_owned(), ShaderDefValue::Bool(true));
        }
        let composed = composer.make_naga_module(NagaModuleDescriptor {
            source: self.source,
            file_path: self.file,
            shader_defs,
            ..Default::default()
        });
        composed.map_err(|e| failure(composer, &format!("{} ({model:?})", self.file), &e))
    }
}

#[cfg(test)]
mod tests {
    use super::super::{fins, marched, planes, shells, skin, strands};
    use super::*;

    #[test]
    fn every_pass_composes_and_validates_under_both_models() {
        let shaders = [
            &skin::SHADER,
            &fins::SHADER,
            &shells::SHADER,
            &marched::SHADER,
            &planes::SHADER,
            &strands::SHADER,
        ];
        for shader in shaders {
            for model in [Model::KajiyaKay, Model::Prt] {
                let module = shader.module(model).unwrap();
                let mut validator = wgpu::naga::valid::Validator::new(
                    wgpu::naga::valid::ValidationFlags::all(),
                    wgpu::naga::valid::Capabilities::default(),
                );
                validator
                    .validate(module)
                    .unwrap_or_else(|e| panic!("{} ({model:?}): {e:?}", shader.file));
                let entry_points: Vec<_> = module.entry_points.iter().map(|e| e.name.as_str()).collect();
                assert_eq!(entry_points, ["vs_main", "fs_main"], "{}", shader.file);
            }
        }
    }

    #[test]
    fn a_shader_that_does_not_compose_is_a_render_error() {
        // An item of a module that does not exist.
        static BROKEN: PassShader = PassShader::new(
            "broken.wgsl",
            "#import pelt::nowhere::f\nfn g() -> f32 { return f(); }\n",
        );
        for model in [Model::KajiyaKay, Model::Prt] {
            match BROKEN.module(model) {
                Err(PeltError::Render(e)) => assert!(e.contains("broken.wgsl"), "{e}"),
                other => panic!("{model:?}: {other:?}"),
            }
        }
    }
}
