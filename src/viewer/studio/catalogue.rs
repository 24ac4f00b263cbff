//! The models and materials the 3D view can show, and which of them it shows.

use std::path::Path;

use crate::error::Result;
use crate::live::PaintSession;
use crate::material::Material;
use crate::scene::{builtin_models, model_meshes, CpuMesh, UvRule};

/// A model the 3D view can show. Built-in models are loaded when first picked.
pub(super) struct ModelEntry {
    pub name: String,
    pub meshes: Vec<CpuMesh>,
}

/// A material the 3D view can show. `None`: the live painting's.
pub(super) struct MaterialEntry {
    pub name: String,
    pub material: Option<Material>,
}

/// Models and materials, each with the one shown.
pub(super) struct Catalogue {
    pub models: Vec<ModelEntry>,
    pub model: usize,
    pub materials: Vec<MaterialEntry>,
    pub material: usize,
    /// Where every model's texture coordinates come from (`view --uv`), as in `render`.
    pub uv: UvRule,
}

impl Catalogue {
    /// The built-in models and the live painting's material, plus what the command line
    /// named; those are shown.
    pub fn new(model: (String, Vec<CpuMesh>), material: Option<(String, Material)>, uv: UvRule) -> Catalogue {
        let model = (model.0, uv.apply(model.1).0);
        let mut models: Vec<ModelEntry> =
            builtin_models().iter().map(|n| ModelEntry { name: n.to_string(), meshes: Vec::new() }).collect();
        let shown = match models.iter().position(|m| m.name == model.0) {
            Some(k) => {
                models[k].meshes = model.1;
                k
            }
            None => {
                models.push(ModelEntry { name: model.0, meshes: model.1 });
                models.len() - 1
            }
        };
        let mut catalogue = Catalogue {
            models,
            model: shown,
            materials: vec![MaterialEntry { name: LIVE.into(), material: None }],
            material: 0,
            uv,
        };
        if let Some((name, m)) = material {
            catalogue.add_material(name, m);
        }
        catalogue
    }

    pub fn model_name(&self) -> &str {
        &self.models[self.model].name
    }

    pub fn material_name(&self) -> &str {
        &self.materials[self.material].name
    }

    /// Whether the live painting's material is the one shown.
    pub fn shows_live(&self) -> bool {
        self.materials[self.material].material.is_none()
    }

    /// The material shown: a stored one, or the live painting's fit.
    pub fn current<'a>(&'a self, session: &'a PaintSession) -> Option<&'a Material> {
        match &self.materials[self.material].material {
            Some(m) => Some(m),
            None => session.material(),
        }
    }

    /// Adds a material and shows it.
    pub fn add_material(&mut self, name: String, material: Material) {
        self.materials.push(MaterialEntry { name, material: Some(material) });
        self.material = self.materials.len() - 1;
    }

    /// Shows the next stored material (`delta` 1) or the previous one (-1), around the list;
    /// from the live painting's, the first or the last.
    pub fn step(&mut self, delta: isize) {
        let stored = self.materials.len() - 1;
        if stored == 0 {
            return;
        }
        self.material = match self.material {
            0 if delta > 0 => 1,
            0 => stored,
            k => 1 + (k as isize - 1 + delta).rem_euclid(stored as isize) as usize,
        };
    }

    /// Adds a model (not shown yet); its index.
    pub fn add_model(&mut self, name: String, meshes: Vec<CpuMesh>) -> usize {
        self.models.push(ModelEntry { name, meshes: self.uv.apply(meshes).0 });
        self.models.len() - 1
    }

    /// The meshes of model `k`, loading a built-in one the first time.
    pub fn meshes(&mut self, k: usize) -> Result<&[CpuMesh]> {
        let entry = &mut self.models[k];
        if entry.meshes.is_empty() {
            entry.meshes = self.uv.apply(model_meshes(&entry.name)?).0;
        }
        Ok(&entry.meshes)
    }
}

/// The name the material list gives the live painting's material.
pub(super) const LIVE: &str = "painting (live)";

/// The name a material directory is listed under.
pub(super) fn entry_name(path: &Path) -> String {
    path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_else(|| path.display().to_string())
}
