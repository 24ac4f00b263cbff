//! Scenes: meshes (node transforms applied), one camera and one light, loaded from glTF 2.0
//! or built from presets. Conventions are fixed by DESIGN.md: the camera looks along -Z of its
//! node with +Y up; the light is KHR_lights_punctual (directional or point, 1/d² falloff).
//!
//! - [`load`] / [`Scene::load`]: a .gltf or .glb scene; [`Scene::load_model`] /
//!   [`model_meshes`]: only its meshes.
//! - [`Scene::from_preset`]: a built-in model ([`builtin_models`]) or any model file, framed
//!   for a standard view and light ([`presets`], thesis 4.1).
//! - [`write_gltf`] / [`Scene::write_gltf`]: one self-contained scene.gltf that loads back as
//!   the same scene.
//!
//! Tangent frames follow glTF: tangent along increasing $u$, bitangent $(n \times t)\,w$
//! towards decreasing $v$ (up the texture image). On the built-in sphere this is the frame of
//! [`crate::brdf::SphereView::frame`].

use glam::{Mat4, Vec2, Vec3, Vec4};

/// A triangle mesh on the host, in world space (its node transform already applied).
#[derive(Clone, Debug, Default)]
pub struct CpuMesh {
    pub positions: Vec<Vec3>,
    /// Unit shading normals, one per vertex (generated smooth normals when the file has none).
    pub normals: Vec<Vec3>,
    /// MikkTSpace tangents (xyz, w = bitangent sign), when the file has them or they were made.
    pub tangents: Option<Vec<Vec4>>,
    /// Texture coordinates (TEXCOORD_0), when the file has them.
    pub uvs: Option<Vec<Vec2>>,
    /// Triangle list.
    pub indices: Vec<u32>,
}

/// How the camera projects.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Projection {
    /// `yfov` in radians, vertical. `aspect` is the file's aspectRatio, if it has one.
    Perspective { yfov: f32, aspect: Option<f32>, znear: f32, zfar: Option<f32> },
    /// Half extents of the view volume.
    Orthographic { xmag: f32, ymag: f32, znear: f32, zfar: f32 },
}

/// A camera: world-from-camera transform (the camera looks along its local -Z, +Y up).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub world_from_camera: Mat4,
    pub projection: Projection,
}

/// The one light of a scene. Colour times intensity scales the light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Light {
    /// `direction` is the unit direction the light travels (its node's -Z), world space.
    Directional { direction: Vec3, color: Vec3, intensity: f32 },
    /// Point light with glTF 1/d² falloff.
    Point { position: Vec3, color: Vec3, intensity: f32 },
}

/// Meshes, one camera, one light.
#[derive(Clone, Debug)]
pub struct Scene {
    pub meshes: Vec<CpuMesh>,
    pub camera: Camera,
    pub light: Light,
}

impl Camera {
    /// The camera's position in world space.
    pub fn position(&self) -> Vec3 {
        self.world_from_camera.w_axis.truncate()
    }

    /// The unit direction the camera looks along (its node's -Z), world space.
    pub fn forward(&self) -> Vec3 {
        self.world_from_camera.transform_vector3(-Vec3::Z).normalize()
    }

    /// The inverse of [`Camera::world_from_camera`].
    pub fn camera_from_world(&self) -> Mat4 {
        self.world_from_camera.inverse()
    }
}

impl Scene {
    /// The sphere around all vertices of all meshes ([`BoundingSphere::of`]); `None` when there
    /// are no vertices.
    pub fn bounding_sphere(&self) -> Option<BoundingSphere> {
        BoundingSphere::of(&self.meshes)
    }
}

/// Loads a glTF 2.0 scene (.gltf or .glb); see [`Scene::load`].
pub fn load(path: impl AsRef<std::path::Path>) -> crate::Result<Scene> {
    Scene::load(path)
}

/// Writes `scene` as one self-contained .gltf file; see [`Scene::write_gltf`].
pub fn write_gltf(scene: &Scene, path: impl AsRef<std::path::Path>) -> crate::Result<()> {
    scene.write_gltf(path)
}

mod accessor;
mod budget;
mod json;
mod load;
mod mesh;
pub mod preset;
mod sources;
mod uv;
mod write;

pub use budget::{MAX_TRIANGLES, MAX_VERTICES};
pub use mesh::BoundingSphere;
pub use uv::{box_uvs, spherical_uvs, UvRule};
pub use preset::{
    builtin_model, builtin_models, frame, model_meshes, preset, preset_names, presets, sphere_mesh, Preset,
};
