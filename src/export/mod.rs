//! Materials out into other tools (issue 38): a glTF 2.0 binary with the closest
//! metallic-roughness material and the exact factored one packed beside it ([`gltf`],
//! [`pbr_fit`]), and MatCaps ([`matcap`]).
//!
//! ```text
//! Material + its scenes ──coverage──► Directions (covered, all)
//! Material + Directions ──pbr_fit──► Pbr + relative RMS (covered, all)
//! varying Material + Directions ──pbr_map──► Pbr per texel (textures) + relative RMS
//! model meshes + Pbr + packed Material ──gltf──► OUT.glb
//! Material + light ──matcap──► front-view sphere image (PNG, or EXR with diffuse/specular layers)
//! ```

pub mod coverage;
pub mod gltf;
pub mod matcap;
pub mod pbr;
pub mod pbr_fit;
pub mod pbr_map;

use std::path::Path;

use crate::error::Result;
use crate::material::{packed, Material};
use crate::scene::CpuMesh;
use coverage::Directions;
use pbr_fit::Approximation;
use pbr_map::MapApproximation;

/// What [`export_gltf`] wrote and how close its PBR material is.
#[derive(Clone, Debug)]
pub struct GltfReport {
    /// The one material closest to the whole surface.
    pub approximation: Approximation,
    /// For a material that varies over the surface, the per-texel material the file holds.
    pub textured: Option<MapApproximation>,
    /// Direction pairs the covered error is over (0: none known, it is over all directions).
    pub covered_pairs: usize,
    /// The scenes the covered directions came from.
    pub scenes: Vec<std::path::PathBuf>,
    pub bytes: usize,
}

/// Fits the PBR approximation of `material` (loaded from `material_path`, whose scenes say
/// what its paintings covered) and writes `meshes` with both materials to `out` (.glb).
pub fn export_gltf(material_path: &Path, material: &Material, meshes: &[CpuMesh], out: &Path) -> Result<GltfReport> {
    let covered = Directions::covered(material_path, material);
    let all = Directions::all();
    let approximation = pbr_fit::fit(material, covered.as_ref(), &all);
    let textured = material.needs_uv().then(|| pbr_map::fit(material, covered.as_ref(), &all, pbr_map::resolution(material)));
    let (pbr, textures) = match &textured {
        Some(t) => (t.map.factors(), Some(t.map.textures()?)),
        None => (approximation.pbr, None),
    };
    let glb = gltf::Glb { meshes, pbr, textures, factored: packed::pack(material)? };
    let bytes = gltf::to_bytes(&glb)?;
    crate::commit::write_atomic(out, &bytes)?;
    let (covered_pairs, scenes) = covered.map_or((0, Vec::new()), |c| (c.len(), c.scenes));
    Ok(GltfReport { approximation, textured, covered_pairs, scenes, bytes: bytes.len() })
}

/// The light of the first scene a material's paintings were made in
/// ([`coverage::scene_files`]), towards it, in that camera's frame (x right, y up, z to the
/// viewer): a lit sphere's own light. `None` when no scene is found.
pub fn picture_light(material_path: &Path, material: &Material) -> Option<glam::DVec3> {
    for path in coverage::scene_files(material_path, material) {
        let Ok((scene, _)) = crate::scene::Scene::load_with_notes(&path) else { continue };
        let from_camera = scene.camera.camera_from_world();
        let towards = match scene.light {
            crate::scene::Light::Directional { direction, .. } => -direction,
            // A point light's direction from the model's centre.
            crate::scene::Light::Point { position, .. } => {
                let centre = scene.bounding_sphere().map_or(glam::Vec3::ZERO, |b| b.center);
                position - centre
            }
        };
        let l = from_camera.transform_vector3(towards).as_dvec3();
        if l.length() > 0.0 {
            return Some(l.normalize());
        }
    }
    None
}
