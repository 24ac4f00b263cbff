//! Scenes: meshes (node transforms applied), one camera and one light, loaded from glTF 2.0
//! or built from presets. Conventions are fixed by DESIGN.md: the camera looks along -Z of its
//! node with +Y up; the light is KHR_lights_punctual (directional or point, 1/d² falloff).

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
