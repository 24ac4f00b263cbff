//! Which (light, view) directions a material's paintings covered, and all directions.
//!
//! A factored material is evidence where its paintings had pixels and extrapolation
//! elsewhere (thesis 5.3), so an approximation is fitted and judged on the covered directions
//! first. They are rebuilt from the scenes the paintings were made in: `MAT/scene.gltf` (a
//! lit sphere's) and every `.gltf`/`.glb` in the material's provenance sources that still
//! exists. Each mesh vertex the camera faces is one direction pair in its local frame
//! (normal, and the mesh's tangent or a frame about $+y$), weighted by $\cos\theta_v$, the
//! share of the image its surface takes. Occlusion is ignored: a vertex hidden behind
//! another part of the model counts as seen.

use std::f64::consts::PI;
use std::path::{Path, PathBuf};

use glam::{DVec2, DVec3};

use crate::factor::Query;
use crate::material::Material;
use crate::scene::{CpuMesh, Light, Projection, Scene};

/// Most direction pairs taken from one scene: vertices are strided down to it (a sphere's
/// front half at 128×64 segments is about 4000; more add time, not coverage).
const MAX_PER_SCENE: usize = 20_000;

/// Points per hemisphere of [`Directions::all`]: 48² = 2304 pairs, the light and the view
/// each within 5° of any direction above the horizon.
const HEMISPHERE_POINTS: usize = 48;

/// Direction pairs with weights.
#[derive(Clone, Debug, Default)]
pub struct Directions {
    pub queries: Vec<Query>,
    pub weights: Vec<f64>,
    /// The scenes the pairs came from (empty for [`Directions::all`]).
    pub scenes: Vec<PathBuf>,
}

impl Directions {
    /// Every light and view direction above the horizon, uniform in solid angle (a
    /// Fibonacci lattice on each hemisphere), texture coordinates spread over the square.
    pub fn all() -> Directions {
        let points = hemisphere(HEMISPHERE_POINTS);
        let mut queries = Vec::with_capacity(points.len() * points.len());
        for (i, &l) in points.iter().enumerate() {
            for (j, &v) in points.iter().enumerate() {
                let k = (i * points.len() + j) as f64;
                // The golden-ratio lattice on the unit square, for uv.
                let uv = DVec2::new((k * 0.618_033_988_749_895).fract(), (k + 0.5) / (points.len() * points.len()) as f64);
                queries.push(Query { l, v, uv });
            }
        }
        let weights = vec![1.0; queries.len()];
        Directions { queries, weights, scenes: Vec::new() }
    }

    /// The directions the paintings of `material` (loaded from `path`) covered, when the
    /// scenes they were made in can be found (module documentation); `None` otherwise.
    pub fn covered(path: &Path, material: &Material) -> Option<Directions> {
        let mut out = Directions::default();
        for scene_path in scene_files(path, material) {
            // A scene that no longer loads tells nothing: the others may.
            let Ok((scene, _notes)) = Scene::load_with_notes(&scene_path) else { continue };
            let before = out.queries.len();
            for mesh in &scene.meshes {
                seen_from(&scene, mesh, &mut out);
            }
            if out.queries.len() > before {
                out.scenes.push(scene_path);
            }
        }
        (!out.queries.is_empty()).then_some(out)
    }

    pub fn len(&self) -> usize {
        self.queries.len()
    }

    pub fn is_empty(&self) -> bool {
        self.queries.is_empty()
    }
}

/// `n` unit directions above the horizon, uniform in solid angle (Fibonacci lattice).
fn hemisphere(n: usize) -> Vec<DVec3> {
    let golden = PI * (3.0 - 5f64.sqrt());
    (0..n)
        .map(|i| {
            // Uniform in z = cos θ on (0, 1]: equal solid angle per point.
            let z = 1.0 - (i as f64 + 0.5) / n as f64;
            let r = (1.0 - z * z).max(0.0).sqrt();
            let phi = golden * i as f64;
            DVec3::new(r * phi.cos(), r * phi.sin(), z)
        })
        .collect()
}

/// The scene files a material's paintings were made in: `MAT/scene.gltf`, then every
/// provenance source ending in .gltf or .glb, as written or beside the material.
pub fn scene_files(path: &Path, material: &Material) -> Vec<PathBuf> {
    let dir = if path.is_dir() { path.to_path_buf() } else { path.parent().map(Path::to_path_buf).unwrap_or_default() };
    let mut found: Vec<PathBuf> = Vec::new();
    let mut push = |p: PathBuf| {
        if p.is_file() && !found.iter().any(|f| f == &p) {
            found.push(p);
        }
    };
    push(dir.join("scene.gltf"));
    for source in &material.provenance.sources {
        let s = Path::new(source);
        let is_scene = s.extension().and_then(|e| e.to_str()).is_some_and(|e| e.eq_ignore_ascii_case("gltf") || e.eq_ignore_ascii_case("glb"));
        if is_scene {
            push(s.to_path_buf());
            if let Some(name) = s.file_name() {
                push(dir.join(name));
            }
        }
    }
    found
}

/// The direction pairs of the vertices of `mesh` the camera of `scene` faces.
fn seen_from(scene: &Scene, mesh: &CpuMesh, out: &mut Directions) {
    let stride = mesh.positions.len().div_ceil(MAX_PER_SCENE).max(1);
    let camera = scene.camera.position().as_dvec3();
    let forward = scene.camera.forward().as_dvec3();
    let orthographic = matches!(scene.camera.projection, Projection::Orthographic { .. });
    for k in (0..mesh.positions.len()).step_by(stride) {
        let p = mesh.positions[k].as_dvec3();
        let n = mesh.normals[k].as_dvec3().normalize_or_zero();
        let v = if orthographic { -forward } else { (camera - p).normalize_or_zero() };
        let cos_v = n.dot(v);
        if n == DVec3::ZERO || cos_v <= 0.0 {
            continue;
        }
        let l = match scene.light {
            Light::Directional { direction, .. } => -direction.as_dvec3().normalize_or_zero(),
            Light::Point { position, .. } => (position.as_dvec3() - p).normalize_or_zero(),
        };
        let (t, b) = tangent_frame(n, mesh.tangents.as_ref().map(|t| t[k]));
        let local = |d: DVec3| DVec3::new(d.dot(t), d.dot(b), d.dot(n));
        let uv = mesh.uvs.as_ref().map_or(DVec2::ZERO, |uv| uv[k].as_dvec2());
        out.queries.push(Query { l: local(l), v: local(v), uv });
        out.weights.push(cos_v);
    }
}

/// Tangent and bitangent at normal `n`: the mesh's tangent made orthogonal to `n` (glTF:
/// bitangent $(n \times t)\,w$), or, without one, the tangent along azimuth about $+y$.
fn tangent_frame(n: DVec3, tangent: Option<glam::Vec4>) -> (DVec3, DVec3) {
    if let Some(t4) = tangent {
        let t = (t4.truncate().as_dvec3() - n * n.dot(t4.truncate().as_dvec3())).normalize_or_zero();
        if t != DVec3::ZERO {
            let w = if t4.w < 0.0 { -1.0 } else { 1.0 };
            return (t, n.cross(t) * w);
        }
    }
    let (t, b, _) = crate::brdf::SphereView::frame(n);
    (t, b)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hemisphere_is_above_the_horizon_and_balanced() {
        let h = hemisphere(400);
        assert!(h.iter().all(|d| d.z > 0.0 && (d.length() - 1.0).abs() < 1e-12));
        // Mean z of a uniform hemisphere is 1/2; mean x and y vanish.
        let mean = h.iter().fold(DVec3::ZERO, |s, d| s + *d) / h.len() as f64;
        assert!((mean.z - 0.5).abs() < 1e-3 && mean.x.abs() < 0.02 && mean.y.abs() < 0.02, "{mean}");
    }
}
